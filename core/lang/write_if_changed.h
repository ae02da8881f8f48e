#pragma once
// How the build-time tools (core/lang/embed_library.cc, core/lang/compile_types_tool.cc) write
// what they generate. Standard library only: the embedding tool runs before momenta exists.

#include <fstream>
#include <iterator>
#include <string>

namespace momenta {

/// Writes `text` to `path` unless the file holds it already, so that a rebuild does not recompile
/// what includes it. False when the file cannot be written.
inline bool WriteIfChanged(const std::string& path, const std::string& text) {
  {
    std::ifstream old(path, std::ios::binary);
    const std::string before((std::istreambuf_iterator<char>(old)), std::istreambuf_iterator<char>());
    if (old && before == text) return true;
  }
  std::ofstream file(path, std::ios::binary);
  file << text;
  return static_cast<bool>(file);
}

}  // namespace momenta
