#include "app/plugin.h"

#include <dlfcn.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <vector>

namespace momenta {

namespace {

namespace fs = std::filesystem;

/// The directories searched, in order (see plugin.h).
std::vector<fs::path> PluginDirectories() {
  std::vector<fs::path> dirs;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    dirs.push_back(self.parent_path());
    dirs.push_back(self.parent_path().parent_path() / "lib" / "momenta");
  }
  return dirs;
}

struct Loaded {
  const void* table = nullptr;
  std::string why;
};

}  // namespace

std::string FindPlugin(const std::string& file) {
  for (const fs::path& dir : PluginDirectories()) {
    const fs::path path = dir / file;
    if (access(path.c_str(), R_OK) == 0) return path.string();
  }
  return "";
}

const void* LoadPlugin(const std::string& file, const char* symbol, bool global, std::string* why) {
  static std::mutex mutex;
  static std::map<std::string, Loaded> loaded;
  std::lock_guard<std::mutex> lock(mutex);
  auto [it, fresh] = loaded.try_emplace(file);
  Loaded& plugin = it->second;
  if (fresh) {
    const std::string path = FindPlugin(file);
    if (path.empty()) {
      plugin.why = "the plugin " + file + " is not installed (looked in";
      for (const fs::path& dir : PluginDirectories()) plugin.why += " " + dir.string();
      plugin.why += ")";
    } else if (void* handle = dlopen(path.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL))) {
      using TableFunction = const void* (*)();
      auto function = reinterpret_cast<TableFunction>(dlsym(handle, symbol));
      const void* table = function ? function() : nullptr;
      if (!table || *static_cast<const int*>(table) != kPluginAbi) {
        plugin.why = "the plugin " + path + " is from another build of momenta (reinstall it)";
      } else {
        plugin.table = table;
      }
    } else {
      const char* error = dlerror();
      plugin.why = "cannot load the plugin " + path + ": " + (error ? error : "unknown error");
    }
  }
  if (!plugin.table && why) *why = plugin.why;
  return plugin.table;
}

}  // namespace momenta
