// momenta_compile_types OUTPUT: writes the library's component types, parsed and in their scalar
// form, as the C++ tables core/lang/compiled_types.cc compiles in (BuiltinLibrary then reads a
// type from its bytes instead of parsing its text at every run). Run by the build after
// momenta_core; a library type that does not parse fails the build here.

#include <exception>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>

#include "core/lang/builtin_library.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: momenta_compile_types OUTPUT\n";
    return 2;
  }
  std::string text;
  try {
    text = momenta::CompileLibraryTypes();
  } catch (const std::exception& e) {
    std::cerr << "momenta_compile_types: " << e.what() << "\n";
    return 1;
  }
  // Written only when it changed, so that a rebuild does not recompile what includes it.
  {
    std::ifstream old(argv[1], std::ios::binary);
    const std::string before((std::istreambuf_iterator<char>(old)), std::istreambuf_iterator<char>());
    if (old && before == text) return 0;
  }
  std::ofstream file(argv[1], std::ios::binary);
  file << text;
  return file ? 0 : 1;
}
