#pragma once
// Where the binary finds its data, installed or in a build tree: <prefix>/share/dgmpm next to
// <prefix>/bin (the build tree mirrors that layout: build/share/dgmpm links to the sources'
// scenes/ and reports/), never a path compiled in from the build machine.

#include <string>

namespace dgmpm {

const char* version();  // the project's version, e.g. "0.2.0"

// $DGMPM_DATA_DIR when set, else <directory of the running binary>/../share/dgmpm.
std::string data_directory();
// data_directory()/relative; throws std::runtime_error naming where it looked when it is missing.
std::string data_file(const std::string& relative);

}  // namespace dgmpm
