#pragma once
// Expected<T>: a computed value, or the reason it could not be computed (the project's
// status + reason idiom for functions that return a value; docs/architecture.md, "Failures").
// It lives in the lowest module so that every module can use it; it is project vocabulary, so
// it is in namespace terratraj, not terratraj::terrain.
//
//   Expected<Guess> guess = guessFromPath(path, problem);
//   if (!guess) return fail(guess.reason());
//   use(*guess);

#include <optional>
#include <string>
#include <utility>

namespace terratraj {

/// The reason of a failed computation, converted to any Expected<T>.
struct Unexpected {
  std::string reason;  ///< why, one line, naming what failed
};

/// A failure with `reason` (non-empty by convention).
inline Unexpected unexpected(std::string reason) { return Unexpected{std::move(reason)}; }

/// A value of T or a reason. Accessing the value of a failure is a precondition violation
/// (std::bad_optional_access).
template <typename T>
class Expected {
 public:
  /// A success holding `value`.
  Expected(T value) : value_(std::move(value)) {}  // NOLINT: implicit, as std::expected
  /// A failure.
  Expected(Unexpected failure) : reason_(std::move(failure.reason)) {}  // NOLINT

  /// Whether it holds a value.
  bool ok() const { return value_.has_value(); }
  explicit operator bool() const { return ok(); }

  const T& value() const { return value_.value(); }
  T& value() { return value_.value(); }
  const T& operator*() const { return value(); }
  T& operator*() { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

  /// Why there is no value ("" for a success).
  const std::string& reason() const { return reason_; }

 private:
  std::optional<T> value_;
  std::string reason_;
};

}  // namespace terratraj
