// Result and Status: how every API boundary in Strata reports bad input without throwing.
// A failed call returns an Error (a code plus a message naming what was wrong) and leaves the world
// unchanged. Plain values; safe to pass between threads.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace strata {

/// What kind of bad input or state an API call ran into.
enum class ErrorCode {
  kInvalidArgument,   ///< NaN/Inf, negative sizes, out-of-range settings
  kDegenerateShape,   ///< a shape that has no volume or no triangles
  kStaleBodyId,       ///< the BodyID's generation no longer matches (body destroyed) or index unknown
  kInvalidState,      ///< e.g. adding a body that is already in the world
  kCapacityExceeded,  ///< the BodyManager is full
  kParseError,        ///< a file that could not be read or parsed
};

/// A failed call: the code for programs, the message for people.
struct Error {
  ErrorCode code;
  std::string message;
};

/// The outcome of a call that returns nothing on success.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT: implicit on purpose

  static Status Ok() { return {}; }
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const Error& error() const {
    assert(!ok_);
    return error_;
  }
  const std::string& message() const { return error_.message; }

 private:
  Error error_{ErrorCode::kInvalidArgument, {}};
  bool ok_ = true;
};

/// The outcome of a call that produces a T on success.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : storage_(std::move(value)) {}      // NOLINT: implicit on purpose
  Result(Error error) : storage_(std::move(error)) {}  // NOLINT: implicit on purpose

  bool ok() const { return std::holds_alternative<T>(storage_); }
  explicit operator bool() const { return ok(); }
  T& value() {
    assert(ok());
    return std::get<T>(storage_);
  }
  const T& value() const {
    assert(ok());
    return std::get<T>(storage_);
  }
  T& operator*() { return value(); }
  const T& operator*() const { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  const Error& error() const {
    assert(!ok());
    return std::get<Error>(storage_);
  }
  Status status() const { return ok() ? Status() : Status(error()); }

 private:
  std::variant<T, Error> storage_;
};

/// Shorthand for building an error at an API boundary.
inline Error MakeError(ErrorCode code, std::string message) {
  return Error{code, std::move(message)};
}

}  // namespace strata
