// A value or an error message: how data-dependent failures travel (C++20 has no std::expected).
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace kfw {

// Exit codes, the same for every command and front end (README "Exit codes"):
//   0  the command did its work (a physical outcome, e.g. a ball leaving the beam, is a result);
//   2  the command, an argument, a preset, a data file or an output path is invalid — found
//      before any work, so nothing is written;
//   1  the work failed (a write error, a numerical breakdown that stops a run).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;
inline constexpr int kExitInvalid = 2;

struct Error {
  std::string message;
  int exit_code = kExitInvalid;  // kExitInvalid for bad input, kExitFailed for failed work
};

// An error found while doing the work (exit 1), not in the input.
inline Error failure(std::string message) {
  return Error{std::move(message), kExitFailed};
}

template <typename T>
class Expected {
 public:
  Expected(T value) : v_(std::move(value)) {}  // NOLINT: implicit by design
  Expected(Error e) : v_(std::move(e)) {}      // NOLINT: implicit by design

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  const T& value() const& { return std::get<0>(v_); }
  T& value() & { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }
  const std::string& error() const { return std::get<1>(v_).message; }
  // The error itself (message and exit code), to pass on unchanged.
  const Error& err() const { return std::get<1>(v_); }
  int exit_code() const { return ok() ? kExitOk : std::get<1>(v_).exit_code; }

 private:
  std::variant<T, Error> v_;
};

// Success without a value.
struct Ok {};
using Status = Expected<Ok>;

}  // namespace kfw
