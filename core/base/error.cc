#include "core/base/error.h"

#include <cstdio>
#include <cstdlib>
#include <deque>
#include <mutex>
#include <string_view>
#include <unordered_map>

namespace momenta {

namespace {

/// Every file name a SourceLoc has named, by number (0: none). Names are never removed, and a
/// deque does not move its elements, so a reference to one stays valid after the lock.
struct FileNames {
  std::mutex mutex;
  std::deque<std::string> names{std::string()};
  std::unordered_map<std::string_view, uint32_t> number{{std::string_view(names.front()), 0}};
};

FileNames& Files() {
  static FileNames* files = new FileNames();  // never destroyed: locations outlive static order
  return *files;
}

uint32_t Intern(const std::string& name) {
  FileNames& f = Files();
  std::lock_guard<std::mutex> lock(f.mutex);
  auto at = f.number.find(name);
  if (at != f.number.end()) return at->second;
  const auto k = static_cast<uint32_t>(f.names.size());
  f.names.push_back(name);
  f.number.emplace(f.names.back(), k);
  return k;
}

}  // namespace

SourceLoc::SourceLoc(const std::string& file_name, int line_number, int column_number)
    : line(line_number), column(column_number), file_(Intern(file_name)) {}

const std::string& SourceLoc::file() const {
  FileNames& f = Files();
  std::lock_guard<std::mutex> lock(f.mutex);
  return f.names[file_];
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
