#pragma once
#include <stdexcept>
#include <string>

namespace masq {
// Every error masq reports: what failed and why, in one line.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
} // namespace masq
