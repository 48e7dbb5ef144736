// Status and Result<T>: expected failures (bad input, storage, transport) travel as values that
// carry a one-line message naming the file, line, field or entity. Broken invariants abort instead.
#pragma once

#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace fleetloc {

enum class StatusCode {
  kOk = 0,
  kInvalidInput,  // the caller's data breaks the contract (maps to exit status 2)
  kNotFound,      // a named file, tile or entity does not exist (exit status 2)
  kInternal,      // anything else: I/O failure, library error (exit status 1)
};

class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status Ok() { return {}; }
  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }

  // Exit status per docs/formats.md: 0 success, 2 bad input, 1 otherwise.
  int ExitCode() const {
    switch (code_) {
      case StatusCode::kOk:
        return 0;
      case StatusCode::kInvalidInput:
      case StatusCode::kNotFound:
        return 2;
      default:
        return 1;
    }
  }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

inline Status InvalidInput(std::string message) {
  return {StatusCode::kInvalidInput, std::move(message)};
}
inline Status NotFound(std::string message) { return {StatusCode::kNotFound, std::move(message)}; }
inline Status Internal(std::string message) { return {StatusCode::kInternal, std::move(message)}; }

// Result<T> holds either a value or a non-ok Status.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)) {}         // NOLINT: implicit by design
  Result(Status status) : status_(std::move(status)) {  // NOLINT: implicit by design
    if (status_.ok()) {
      std::cerr << "Result constructed from an ok Status without a value\n";
      std::abort();
    }
  }

  bool ok() const { return value_.has_value(); }
  const Status& status() const { return status_; }
  T& value() & { return CheckedValue(); }
  const T& value() const& { return const_cast<Result*>(this)->CheckedValue(); }
  T&& value() && { return std::move(CheckedValue()); }
  T* operator->() { return &CheckedValue(); }
  const T* operator->() const { return &const_cast<Result*>(this)->CheckedValue(); }
  T& operator*() & { return CheckedValue(); }
  const T& operator*() const& { return const_cast<Result*>(this)->CheckedValue(); }

 private:
  T& CheckedValue() {
    if (!value_) {
      std::cerr << "Result::value() on error: " << status_.message() << "\n";
      std::abort();
    }
    return *value_;
  }
  std::optional<T> value_;
  Status status_;
};

// Moves a successful Result into a new *out (for members built in steps that may fail);
// otherwise returns its Status and leaves *out alone.
template <typename T, typename Ptr>
Status AssignTo(Result<T> result, Ptr* out) {
  if (!result.ok()) return result.status();
  *out = Ptr(new T(std::move(result).value()));
  return Status::Ok();
}

// Aborts with a message when a programmer's invariant is broken.
#define FLEETLOC_CHECK(cond)                                                     \
  do {                                                                           \
    if (!(cond)) {                                                               \
      std::cerr << __FILE__ << ":" << __LINE__ << ": check failed: " #cond "\n"; \
      std::abort();                                                              \
    }                                                                            \
  } while (0)

#define FLEETLOC_RETURN_IF_ERROR(expr) \
  do {                                 \
    ::fleetloc::Status _st = (expr);   \
    if (!_st.ok()) return _st;         \
  } while (0)

}  // namespace fleetloc
