// How the tests treat a backend this machine cannot run: a failure, unless
// MASQ_ALLOW_MISSING_BACKENDS=1 (scripts/setup.sh installs every backend, so a missing
// one is a broken setup; the variable is for machines without a driver).
#pragma once
#include "masq/error.h"
#include <cstdlib>
#include <gtest/gtest.h>
#include <string>

namespace masq::test {

inline bool missing_backends_allowed() {
  const char* v = std::getenv("MASQ_ALLOW_MISSING_BACKENDS");
  return v != nullptr && std::string(v) == "1";
}

// make(name), or nullptr after a test failure naming the cause (nullptr and no failure
// when missing backends are allowed). Callers skip the backend on nullptr.
template <class Make>
auto open_or_fail(const std::string& name, Make make) -> decltype(make(name)) {
  try {
    return make(name);
  } catch (const BackendUnavailable& e) {
    if (!missing_backends_allowed())
      ADD_FAILURE() << e.what() << " (scripts/setup.sh installs every backend; set MASQ_ALLOW_MISSING_BACKENDS=1 to skip)";
    return nullptr;
  }
}

// Sets an environment variable (a knob, a fault injection) for the scope of one check.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) { setenv(name, value.c_str(), 1); }
  ~ScopedEnv() { unsetenv(name_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
};

} // namespace masq::test
