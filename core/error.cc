#include "core/error.h"

#include <cstdio>
#include <cstdlib>

namespace momenta {

std::string SourceLoc::ToString() const {
  if (file.empty() && line == 0) return "";
  std::string s = file;
  if (line > 0) {
    s += ":" + std::to_string(line) + ":" + std::to_string(column > 0 ? column : 1);
  }
  return s;
}

SourceLoc SourceLoc::Shifted(int columns) const {
  SourceLoc l = *this;
  if (l.line > 0) l.column += columns;
  return l;
}

static std::string Prefixed(const SourceLoc& loc, const std::string& message) {
  std::string where = loc.ToString();
  return where.empty() ? message : where + ": " + message;
}

ModelError::ModelError(const SourceLoc& loc, const std::string& message)
    : std::runtime_error(Prefixed(loc, message)) {}

void AbortOnInternalError(const char* condition, const char* file, int line,
                          const std::string& message) {
  std::fprintf(stderr, "momenta internal error: %s failed at %s:%d %s\n", condition, file, line,
               message.c_str());
  std::abort();
}

}  // namespace momenta
