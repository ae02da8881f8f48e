// momenta_compile_types OUTPUT: writes the library parsed and serialised (SerializeLibrary: its
// records, connector types, component types in their scalar form, and functions) as the C++
// tables core/lang/compiled_types.cc compiles in; BuiltinLibrary then reads them instead of
// parsing the library's text at every run. Run by the build after momenta_core; a library type
// that does not parse fails the build here.

#include <cstdint>
#include <exception>
#include <iostream>
#include <string>
#include <string_view>

#include "core/lang/builtin_library.h"
#include "core/lang/write_if_changed.h"

namespace {

/// `bytes` as adjacent C++ string literals of three-digit octal escapes and plain characters.
void AppendLiteral(std::string_view bytes, std::string* out) {
  constexpr size_t kLine = 96;
  for (size_t at = 0; at < bytes.size(); at += kLine) {
    *out += "  \"";
    for (const char ch : bytes.substr(at, kLine)) {
      const auto c = static_cast<unsigned char>(ch);
      if (c >= 0x20 && c < 0x7f && c != '"' && c != '\\' && c != '?') {
        *out += static_cast<char>(c);
      } else {
        const char escape[5] = {'\\', static_cast<char>('0' + (c >> 6)), static_cast<char>('0' + ((c >> 3) & 7)),
                                static_cast<char>('0' + (c & 7)), '\0'};
        *out += escape;
      }
    }
    *out += "\"\n";
  }
}

/// The tables of `library` as C++ text.
std::string Tables(const momenta::SerializedLibrary& library) {
  std::string out = "// Written by momenta_compile_types (core/lang/compile_types_tool.cc) when the binary is built.\n";
  out += "static constexpr uint64_t kCompiledLibraryHash = " + std::to_string(library.library_hash) + "ull;\n";
  out += "static const char kCompiledLibraryBytes[] =\n";
  AppendLiteral(library.bytes, &out);
  out += "  \"\";\n";
  out += "static const uint32_t kCompiledLibraryOffsets[] = {";
  for (size_t k = 0; k < library.offsets.size(); ++k) {
    out += (k % 12 == 0 ? "\n  " : " ") + std::to_string(library.offsets[k]) + ",";
  }
  out += "\n};\n";
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: momenta_compile_types OUTPUT\n";
    return 2;
  }
  std::string text;
  try {
    text = Tables(momenta::SerializeLibrary());
  } catch (const std::exception& e) {
    std::cerr << "momenta_compile_types: " << e.what() << "\n";
    return 1;
  }
  return momenta::WriteIfChanged(argv[1], text) ? 0 : 1;
}
