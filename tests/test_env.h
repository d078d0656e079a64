// How the tests treat a backend this machine cannot run: a failure, unless
// MASQ_ALLOW_MISSING_BACKENDS=1 (scripts/setup.sh installs every backend, so a missing
// one is a broken setup; the variable is for machines without a driver).
#pragma once
#include "masq/error.h"
#include "masq/knobs.h"
#include <algorithm>
#include <cstdlib>
#include <gtest/gtest.h>
#include <string>
#include <vector>

namespace masq::test {

inline bool missing_backends_allowed() { return knob_flag(Knob::AllowMissingBackends); }

// make(name), or nullptr after a test failure naming the cause (nullptr and no failure
// when missing backends are allowed), the cause also in *why. Callers skip the backend
// on nullptr: a test of that backend alone with `if (!be) GTEST_SKIP() << why;`, so
// that it reports SKIPPED (or FAILED), never PASSED.
template <class Make>
auto open_or_fail(const std::string& name, Make make, std::string* why = nullptr) -> decltype(make(name)) {
  try {
    return make(name);
  } catch (const BackendUnavailable& e) {
    if (why != nullptr) *why = std::string(e.what()) + " (MASQ_ALLOW_MISSING_BACKENDS=1)";
    if (!missing_backends_allowed())
      ADD_FAILURE() << e.what() << " (scripts/setup.sh installs every backend; set MASQ_ALLOW_MISSING_BACKENDS=1 to skip)";
    return nullptr;
  }
}

// The backends a test that covers "every backend" runs: backend_names() (host/backend.h),
// or only those MASQ_TEST_BACKENDS lists (comma-separated), so that one run can check one
// device's backends (the GPU bundle, scripts/gpu_bundle.sh) or the cpu under valgrind.
// A listed name no backend has fails the test.
inline std::vector<std::string> tested_backends(const std::vector<std::string>& all) {
  const std::string list = knob_text(Knob::TestBackends).value_or("");
  if (list.empty()) return all;
  std::vector<std::string> out;
  for (std::size_t b = 0; b <= list.size();) {
    std::size_t e = list.find(',', b);
    if (e == std::string::npos) e = list.size();
    std::string name = list.substr(b, e - b);
    if (!name.empty()) {
      if (std::find(all.begin(), all.end(), name) == all.end())
        ADD_FAILURE() << "MASQ_TEST_BACKENDS names '" << name << "', no backend";
      else
        out.push_back(name);
    }
    b = e + 1;
  }
  return out;
}

// Sets an environment variable (a knob of include/masq/knobs.h, a fault injection) for
// the scope of one check.
// The variable's earlier value (or its absence) comes back at the end of the scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    const char* old = std::getenv(name);
    had_ = old != nullptr;
    if (had_) old_ = old;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had_) setenv(name_, old_.c_str(), 1);
    else unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  bool had_ = false;
  std::string old_;
};

} // namespace masq::test
