#include "stability/options.hpp"

#include <stdexcept>

namespace dgmpm::stability {

const char* to_string(TimeScheme s) {
  return s == TimeScheme::euler ? "euler" : "rk2";
}
const char* to_string(Criterion c) {
  return c == Criterion::l2 ? "l2" : "monotone";
}
const char* to_string(Model m) {
  return m == Model::advection ? "advection" : "elastic";
}

TimeScheme parse_time_scheme(const std::string& s) {
  if (s == "euler") return TimeScheme::euler;
  if (s == "rk2") return TimeScheme::rk2;
  throw std::invalid_argument("unknown time scheme '" + s + "' (euler or rk2)");
}
Criterion parse_criterion(const std::string& s) {
  if (s == "l2") return Criterion::l2;
  if (s == "monotone") return Criterion::monotone;
  throw std::invalid_argument("unknown criterion '" + s + "' (l2 or monotone)");
}
Model parse_model(const std::string& s) {
  if (s == "advection") return Model::advection;
  if (s == "elastic") return Model::elastic;
  throw std::invalid_argument("unknown model '" + s + "' (elastic or advection)");
}

int polynomial_degree(TimeScheme s) {
  return s == TimeScheme::euler ? 1 : 2;
}

}  // namespace dgmpm::stability
