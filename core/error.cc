#include "core/error.h"

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <set>

namespace momenta {

namespace {
const std::string* Intern(const std::string& name) {
  static std::mutex mutex;
  static std::set<std::string>* names = new std::set<std::string>();
  std::lock_guard<std::mutex> lock(mutex);
  return &*names->insert(name).first;
}
}  // namespace

SourceLoc::SourceLoc(const std::string& file_name, int line_number, int column_number)
    : line(line_number), column(column_number), file_(Intern(file_name)) {}

const std::string& SourceLoc::file() const {
  static const std::string kNone;
  return file_ ? *file_ : kNone;
}

void SourceLoc::set_file(const std::string& file_name) { file_ = Intern(file_name); }

std::string SourceLoc::ToString() const {
  if (file().empty() && line == 0) return "";
  std::string s = file();
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
