// libFuzzer target: `dgmpm courant` arguments (one per line of the input) through the option
// parser and validation, and through the analysis when it is quick (1D layouts). A refusal is an
// exit code with a message; a crash, a sanitizer report or a hang is a finding.
#include "stability/courant_command.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace {
// How far the inputs got, printed at exit (see scene_fuzzer.cpp).
struct Reach {
  long inputs = 0, accepted = 0;
  ~Reach() {
    std::fprintf(stderr, "fuzz_courant_options reach: %ld inputs, %ld accepted\n", inputs,
                 accepted);
  }
} reach;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args(1);
  for (std::size_t i = 0; i < size; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == '\n')
      args.emplace_back();
    else
      args.back().push_back(c);
  }
  if (args.size() > 64) return 0;
  std::ostringstream out, err;
  const int code =
      dgmpm::stability::courant_main(args, out, err, dgmpm::stability::CourantAnalysis::quick);
  ++reach.inputs;
  if (code == 0) ++reach.accepted;
  // Every refusal says why.
  if (code == 2 && err.str().empty() && out.str().empty()) std::abort();
  return 0;
}
