#pragma once
/// Two kinds of check (after Drake's drake_assert.h): ModelError for anything a user or a file can
/// cause, reported with file:line:col and the user's names; MOMENTA_CHECK for the code's own
/// invariants, which aborts. Never MOMENTA_CHECK on user input.

#include <cstdint>
#include <stdexcept>
#include <string>

namespace momenta {

/// A place in a user's file. Lines and columns are 1-based; line 0 means "no place known".
/// The file name is interned: copying a SourceLoc (every flattened variable and equation keeps
/// one) copies a pointer, not a string.
struct SourceLoc {
  SourceLoc() = default;
  SourceLoc(const std::string& file_name, int line_number = 0, int column_number = 0);

  int line = 0;
  int column = 0;

  const std::string& file() const;
  void set_file(const std::string& file_name);

  bool known() const { return line > 0; }
  /// "file:line:col" or the file alone, or "" when nothing is known.
  std::string ToString() const;
  /// The same place moved `columns` characters to the right (for text inside a YAML scalar).
  SourceLoc Shifted(int columns) const;

 private:
  /// The file name's number in a table of every name seen (0: none), so that a location is 12
  /// bytes: the flat system holds one per variable, parameter and equation.
  uint32_t file_ = 0;
};

/// An error in the user's model: exit code 1. The message starts with "file:line:col: ".
class ModelError : public std::runtime_error {
 public:
  ModelError(const SourceLoc& loc, const std::string& message);
  explicit ModelError(const std::string& message) : std::runtime_error(message) {}
};

/// A mistake on the command line rather than in the model file (an unknown -p name): exit code 2.
/// It is a ModelError so that code which only knows about model errors still reports it.
class UsageError : public ModelError {
 public:
  explicit UsageError(const std::string& message) : ModelError(message) {}
};

/// The solver failed: exit code 3. Results computed so far are kept by the caller.
class SolverError : public std::runtime_error {
 public:
  explicit SolverError(const std::string& message) : std::runtime_error(message) {}
};

[[noreturn]] void AbortOnInternalError(const char* condition, const char* file, int line,
                                       const std::string& message);

}  // namespace momenta

#define MOMENTA_CHECK(cond)                                                    \
  do {                                                                         \
    if (!(cond)) ::momenta::AbortOnInternalError(#cond, __FILE__, __LINE__, ""); \
  } while (0)
#define MOMENTA_CHECK_MSG(cond, msg)                                              \
  do {                                                                            \
    if (!(cond)) ::momenta::AbortOnInternalError(#cond, __FILE__, __LINE__, (msg)); \
  } while (0)
