#include "stability/options.hpp"

#include <array>
#include <stdexcept>
#include <string>

namespace dgmpm::stability {

const char* to_string(Criterion c) {
  switch (c) {
    case Criterion::l2:
      return "l2";
    case Criterion::monotone:
      return "monotone";
    case Criterion::budget:
      return "budget";
  }
  return "?";
}
const char* to_string(Model m) {
  return m == Model::advection ? "advection" : "elastic";
}

namespace {

// The value of `all` whose to_string is `s`: one spelling per value, the printed one.
template <class E, class Values>
E parse_named(const std::string& s, const Values& all, const char* what) {
  std::string listed;
  for (E e : all) {
    if (s == to_string(e)) return e;
    listed += (listed.empty() ? "" : " or ") + std::string(to_string(e));
  }
  throw std::invalid_argument("unknown " + std::string(what) + " '" + s + "' (" + listed + ")");
}

}  // namespace

TimeScheme parse_time_scheme(const std::string& s) {
  return parse_named<TimeScheme>(s, time_schemes, "time scheme");
}
Criterion parse_criterion(const std::string& s) {
  return parse_named<Criterion>(s, std::array{Criterion::l2, Criterion::monotone}, "criterion");
}
Model parse_model(const std::string& s) {
  return parse_named<Model>(s, std::array{Model::elastic, Model::advection}, "model");
}

int polynomial_degree(TimeScheme s) {
  return traits(s).stages;
}

int polynomial_degree(const AnalysisSetting& s) {
  return polynomial_degree(s.time) * (s.dim > 1 && s.flux == FluxScheme::ctu ? 2 : 1);
}

}  // namespace dgmpm::stability
