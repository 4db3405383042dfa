// result.h: errors and the Result<T> return type.
//
// Loaders, parsers and constructors of user-described shapes never abort and
// never throw across the public API: they return a Result<T> that holds either
// the value or an Error naming the file, line and column (where there is one)
// and what was expected.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace cmkit {

/// What went wrong, and where.
struct Error {
  std::string message;  ///< what was wrong / what was expected
  std::string file;     ///< file name, empty when the input was not a file
  int line = 0;         ///< 1-based line, 0 when unknown
  int column = 0;       ///< 1-based column, 0 when unknown

  Error() = default;
  /// An error with its message and, when known, its file, line and column.
  explicit Error(std::string msg, std::string fileName = {}, int lineNo = 0, int col = 0)
      : message(std::move(msg)), file(std::move(fileName)), line(lineNo), column(col) {}

  /// "file:line:column: message" (the parts that are known).
  std::string toString() const {
    std::string s;
    if (!file.empty()) {
      s += file;
      if (line > 0) {
        s += ':' + std::to_string(line);
        if (column > 0) s += ':' + std::to_string(column);
      }
      s += ": ";
    } else if (line > 0) {
      s += "line " + std::to_string(line);
      if (column > 0) s += ", column " + std::to_string(column);
      s += ": ";
    }
    return s + message;
  }
};

/// Either a value of type T or an Error.
template <class T>
class [[nodiscard]] Result {
 public:
  /// A successful result.
  Result(T value) : v_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  /// A failed result.
  Result(Error error) : v_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  /// True when the result holds a value.
  bool ok() const { return v_.index() == 0; }
  /// True when the result holds a value.
  explicit operator bool() const { return ok(); }

  /// The value; only when ok().
  T& value() & {
    assert(ok());
    return std::get<0>(v_);
  }
  /// The value; only when ok().
  const T& value() const& {
    assert(ok());
    return std::get<0>(v_);
  }
  /// The value, moved out; only when ok().
  T&& value() && {
    assert(ok());
    return std::get<0>(std::move(v_));
  }
  /// The value's members; only when ok().
  T* operator->() { return &value(); }
  /// The value's members; only when ok().
  const T* operator->() const { return &value(); }
  /// The value; only when ok().
  T& operator*() & { return value(); }
  /// The value; only when ok().
  const T& operator*() const& { return value(); }

  /// The error; only when !ok().
  const Error& error() const {
    assert(!ok());
    return std::get<1>(v_);
  }

 private:
  std::variant<T, Error> v_;
};

/// Result of an operation that yields nothing but can fail.
struct Ok {};
using Status = Result<Ok>;

}  // namespace cmkit
