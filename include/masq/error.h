/// @file masq/error.h
/// The two exception types every part of masq throws. They are shared by the public API
/// and the library's internals, so a caller catches exactly what the backends throw.
#pragma once
#include <stdexcept>
#include <string>

namespace masq {

/// Any failure: bad input (file, array, option), a device error, misuse of the API.
/// what() is one line naming what failed and where (file and byte offset or line,
/// geometry/primitive index, backend and the failing call).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A backend cannot run on this machine (no driver, no device, a missing extension or
/// feature). what() is one line "<backend>: <why>". Other backends stay usable.
class BackendUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

} // namespace masq
