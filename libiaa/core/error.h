// The two tiers of errors (docs/design.md, "Errors").
//
// - `Error` and its subclasses are for bad user input: a malformed expression, an impossible
//   setting, a bad scene file. They carry what a person needs to fix the input (line, column, the
//   key, the allowed range) and are caught once in each tool's main, printed, and turned into a
//   non-zero exit code.
// - Internal invariants are checked with IAA_CHECK, which aborts with file and line: a failed check
//   is a bug in iaa, never the user's fault.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace iaa {

/// Base of every error caused by user input.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A syntax or name error in a text input, with a 1-based line and column.
class ParseError : public Error {
 public:
  ParseError(const std::string& message, int line, int column)
      : Error("line " + std::to_string(line) + ", column " + std::to_string(column) + ": " +
              message),
        line_(line),
        column_(column),
        bare_(message) {}
  int line() const { return line_; }
  int column() const { return column_; }
  /// The message without its position.
  const std::string& bare_message() const { return bare_; }

 private:
  int line_, column_;
  std::string bare_;
};

/// A setting outside its allowed range; the message names the setting and the limits.
class SettingError : public Error {
 public:
  using Error::Error;
};

}  // namespace iaa

/// Checks an internal invariant; aborts with its location when it fails (a bug in iaa).
#define IAA_CHECK(cond)                                                                      \
  do {                                                                                       \
    if (!(cond)) {                                                                           \
      std::fprintf(stderr, "%s:%d: internal check failed: %s\n", __FILE__, __LINE__, #cond); \
      std::abort();                                                                          \
    }                                                                                        \
  } while (0)
