#pragma once
// A test program's scratch folder: its own (two runs of the suite at once share no file), made on
// first use, removed when the program ends with no failure, kept (and named on stderr) after one.
// Include in one file per module: it declares a global fixture.

#include <boost/test/tree/observer.hpp>
#include <boost/test/unit_test.hpp>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace dgmpm::test {

class Scratch : public boost::unit_test::test_observer {
 public:
  static Scratch& instance() {
    static Scratch scratch;
    return scratch;
  }
  const std::filesystem::path& folder() {
    if (folder_.empty()) {
      const std::string module = boost::unit_test::framework::master_test_suite().p_name;
      std::string pattern =
          (std::filesystem::temp_directory_path() / ("dgmpm_" + module + "_XXXXXX")).string();
      if (!::mkdtemp(pattern.data()))
        throw std::runtime_error("cannot make a scratch folder from " + pattern);
      folder_ = pattern;
    }
    return folder_;
  }
  // Called by the fixture when the program ends.
  void finish() {
    if (folder_.empty()) return;
    if (failed_) {
      std::cerr << "a test failed: its files are kept in " << folder_.string() << '\n';
      return;
    }
    std::error_code ignored;
    std::filesystem::remove_all(folder_, ignored);
  }

  void assertion_result(boost::unit_test::assertion_result result) override {
    if (result == boost::unit_test::AR_FAILED) failed_ = true;  // not a warning
  }
  void exception_caught(const boost::execution_exception&) override { failed_ = true; }
  void test_unit_aborted(const boost::unit_test::test_unit&) override { failed_ = true; }
  void test_unit_timed_out(const boost::unit_test::test_unit&) override { failed_ = true; }

 private:
  Scratch() = default;
  std::filesystem::path folder_;
  bool failed_ = false;
};

// The folder (made by the first call).
inline const std::filesystem::path& scratch() {
  return Scratch::instance().folder();
}

struct ScratchCleanup {
  ScratchCleanup() { boost::unit_test::framework::register_observer(Scratch::instance()); }
  ~ScratchCleanup() {
    boost::unit_test::framework::deregister_observer(Scratch::instance());
    Scratch::instance().finish();
  }
};
BOOST_TEST_GLOBAL_FIXTURE(ScratchCleanup);

}  // namespace dgmpm::test
