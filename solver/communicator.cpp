#include "solver/communicator.hpp"

namespace dgmpm {

namespace {
Communicator* launched = nullptr;
}  // namespace

Communicator* launched_ranks() {
  return launched;
}
void set_launched_ranks(Communicator* ranks) {
  launched = ranks;
}

}  // namespace dgmpm
