// The component library (components/*.yaml) compiled into the binary, so the CLI works from any
// folder. The build writes builtin_library_data.inc from the YAML files (see core/CMakeLists.txt).

#include "core/lang/builtin_library.h"

#include <mutex>

#include "core/lang/component_type.h"
#include "core/lang/model_spec.h"
#include "core/lang/yaml_loader.h"

namespace momenta {

namespace {
struct EmbeddedFile {
  const char* name;
  const char* text;
};
#include "builtin_library_data.inc"
}  // namespace

const Library& BuiltinLibrary() {
  static Library* library = [] {
    auto* lib = new Library();
    // Connector types first: component types refer to them.
    for (const EmbeddedFile& f : kEmbeddedLibraryFiles) {
      if (std::string(f.name) == "components/connectors.yaml") LoadLibraryString(f.text, f.name, lib);
    }
    for (const EmbeddedFile& f : kEmbeddedLibraryFiles) {
      if (std::string(f.name) != "components/connectors.yaml") LoadLibraryString(f.text, f.name, lib);
    }
    return lib;
  }();
  return *library;
}

}  // namespace momenta
