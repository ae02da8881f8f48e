// The component library (components/*.yaml) compiled into the binary, so the CLI works from any
// folder. The build writes builtin_library_data.inc from the YAML files (see core/CMakeLists.txt).
//
// Reading all of it (some 120 types, 120 KB of YAML, their equations parsed) took about 10 ms of
// CPU, most of a small model's whole run, which uses a handful of types. So the records and the
// connector types are read at once, the functions together when a text first calls one or a
// lookup first asks for one (a fifth of the ball and pendulum's whole run when read at start),
// and each component type the first time a model names it (LazyTypes). The text's top-level
// entries, one a type, and their short names are found when the binary is built
// (core/lang/embed_library.cc): cutting the ~500 KB of text at every start was a tenth of a small
// model's whole run, and start-up now touches only the text of the entries it reads. An entry is
// read as its own YAML document, preceded by as many empty lines as come before it in its file,
// so that every location (file:line:col) is the one reading the whole file gives; each type is
// turned into its scalar form (core/lang/arrays.h) as it is read, which needs only the connector
// types. The library is one object for the process, never copied (a copy would share the record
// of what was read).
//
// A program that links momenta_compiled_types (the CLI) goes further: the build parsed every
// entry once (SerializeLibrary, run by momenta_compile_types) and the program hands the
// serialised result to UseCompiledLibraryTypes, so the records and connector types are read from
// bytes at start and each component type or function from its bytes on first use; no library
// text is parsed at run time (the ball and pendulum's whole run 23.3 M -> 20.6 M instructions).

#include "core/lang/builtin_library.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "core/lang/arrays.h"
#include "core/lang/component_type.h"
#include "core/lang/model_spec.h"
#include "core/lang/parser.h"
#include "core/lang/type_serial.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/yaml_loader_document.h"
#include "core/lang/yaml_loader_types.h"
#include "core/lang/yaml_loader_values.h"

namespace momenta {

namespace {
struct EmbeddedFile {
  const char* name;
  const char* text;
};
/// One top-level entry of a library file (a type), found when the binary was built. Numbers
/// only, so that the table is not relocated (written) at start.
struct EmbeddedEntry {
  uint32_t name;    ///< offset in kEmbeddedLibraryNames
  uint32_t file;    ///< index in kEmbeddedLibraryFiles
  uint32_t offset;  ///< of its text in the file
  uint32_t length;
  uint32_t line;  ///< the line of the file the text starts at
  char kind;      ///< 'f' a function, 'r' a record, 'k' a connector type, 't' a component type
};
/// A short name (ShortNames) of an entry; sorted by name, then in the files' order.
struct EmbeddedShortName {
  uint32_t name;   ///< offset in kEmbeddedLibraryNames (the tail of the entry's name)
  uint32_t entry;  ///< index in kEmbeddedLibraryEntries
};
// kEmbeddedLibraryFiles; kEmbeddedLibraryNames (each name ended by '\0');
// kEmbeddedLibraryEntries sorted by name (every file's but connectors.yaml);
// kEmbeddedLibraryShortNames. Written by the build (core/lang/embed_library.cc).
#include "builtin_library_data.inc"

constexpr size_t kNumEntries = sizeof(kEmbeddedLibraryEntries) / sizeof(kEmbeddedLibraryEntries[0]);

/// The library as the build parsed it, when UseCompiledLibraryTypes was given it.
CompiledLibraryTypes compiled_types;

/// Entry i's bytes in compiled_types (i = kNumEntries: the records and connector types the
/// library starts with), or empty.
std::string_view CompiledEntry(size_t i) {
  if (compiled_types.bytes == nullptr) return {};
  const uint32_t begin = compiled_types.offsets[i], end = compiled_types.offsets[i + 1];
  return std::string_view(compiled_types.bytes + begin, end - begin);
}

/// The entries of the embedded files other than the connectors, each read on first use.
class BuiltinTypes : public LazyTypes {
 public:
  /// Reads at once the records and the connector types (so that every connector type is known
  /// without a lookup). The functions are read together on first use (ReadFunctions): most
  /// models call none.
  /// With `started`, the library holds them already (read from their compiled bytes).
  BuiltinTypes(Library* library, bool started) : read_(kNumEntries, false) {
    // Every function's name first, so that any text may call one before it is read.
    for (const EmbeddedEntry& entry : kEmbeddedLibraryEntries) {
      if (entry.kind == 'f') RegisterFunction(kEmbeddedLibraryNames + entry.name, -1);
    }
    // Records first: connector types use them.
    for (const char kind : {'r', 'k'}) {
      for (size_t i = 0; i < kNumEntries; ++i) {
        if (kEmbeddedLibraryEntries[i].kind != kind) continue;
        if (started) {
          read_[i] = true;
        } else {
          ReadEntry(i, library);
        }
      }
    }
  }

  void ReadFunctions(Library* library) const override {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    if (functions_read_) return;
    functions_read_ = true;
    for (size_t i = 0; i < kNumEntries; ++i) {
      if (!read_[i] && kEmbeddedLibraryEntries[i].kind == 'f') ReadEntry(i, library);
    }
  }

  /// Reads the type named `name` and every type whose last dotted part is `name`: Library's
  /// short-name rule (a short name is ambiguous when two packages use it, and an unqualified type
  /// of that name comes first) then decides as it would in the whole library.
  void Read(const std::string& name, Library* library) const override {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    if (!asked_.insert(name).second) return;
    const auto by_name = [](const auto& entry, const std::string& n) {
      return std::strcmp(kEmbeddedLibraryNames + entry.name, n.c_str()) < 0;
    };
    const EmbeddedEntry* entry = std::lower_bound(std::begin(kEmbeddedLibraryEntries),
                                                  std::end(kEmbeddedLibraryEntries), name, by_name);
    if (entry != std::end(kEmbeddedLibraryEntries) && kEmbeddedLibraryNames + entry->name == name) {
      const size_t i = static_cast<size_t>(entry - kEmbeddedLibraryEntries);
      if (!read_[i]) ReadEntry(i, library);
    }
    for (const EmbeddedShortName* s =
             std::lower_bound(std::begin(kEmbeddedLibraryShortNames),
                              std::end(kEmbeddedLibraryShortNames), name, by_name);
         s != std::end(kEmbeddedLibraryShortNames) && kEmbeddedLibraryNames + s->name == name;
         ++s) {
      if (!read_[s->entry]) ReadEntry(s->entry, library);
    }
  }

  void ReadAll(Library* library) const override {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    ReadFunctions(library);
    for (size_t i = 0; i < kNumEntries; ++i) {
      if (!read_[i]) ReadEntry(i, library);
    }
  }

 private:
  /// Reads entry `i` into `library`, in its scalar form. The entry is read as its own YAML
  /// document, preceded by as many empty lines as come before it in its file.
  void ReadEntry(size_t i, Library* library) const {
    read_[i] = true;
    // A component type or function the build parsed already: read from its bytes (a tenth of
    // the parse).
    if (const std::string_view bytes = CompiledEntry(i); !bytes.empty()) {
      if (kEmbeddedLibraryEntries[i].kind == 'f') {
        library->AddFunction(DeserializeFunction(bytes));
      } else {
        library->AddComponent(DeserializeComponentType(bytes));
      }
      return;
    }
    const EmbeddedEntry& entry = kEmbeddedLibraryEntries[i];
    const char* file = kEmbeddedLibraryFiles[entry.file].name;
    std::string text(entry.line - 1, '\n');
    text.append(kEmbeddedLibraryFiles[entry.file].text + entry.offset, entry.length);
    const ValueReader reader(file);
    std::unique_ptr<YamlDoc> doc = ParseYamlFile(text, file, "library file");
    Library read;
    read.AddRecordsAndFunctions(*library);
    ReadLibraryEntries(reader, doc->root(), &read, nullptr, false);
    library->AddRecordsAndFunctions(read);
    for (const std::string& name : read.ConnectorNames()) library->AddConnector(*read.FindConnector(name));
    for (const std::string& name : read.ComponentNames()) {
      const ComponentType* t = read.FindComponent(name);
      // The scalar form needs the connector types only, all read before any component type.
      library->AddComponent(NeedsScalarForm(*t, *library) ? ScalarForm(*t, *library) : *t);
    }
  }

  mutable std::vector<bool> read_;  ///< by index in kEmbeddedLibraryEntries
  mutable std::set<std::string> asked_;  ///< names Read has resolved already
  mutable bool functions_read_ = false;
  mutable std::recursive_mutex mutex_;
};

}  // namespace

bool UseCompiledLibraryTypes(const CompiledLibraryTypes& types) {
  // The entries' ranges and one more, the records and connectors the library starts with.
  if (types.library_hash != kEmbeddedLibraryHash || types.entries != kNumEntries + 1) return false;
  compiled_types = types;
  return true;
}

SerializedLibrary SerializeLibrary() {
  const Library& library = BuiltinLibrary();
  // What it holds before any type is read: the records and connector types.
  const std::string start = SerializeRecordsAndConnectors(library);
  SerializedLibrary out;
  out.library_hash = kEmbeddedLibraryHash;
  std::string& bytes = out.bytes;
  out.offsets.push_back(0);
  for (const EmbeddedEntry& entry : kEmbeddedLibraryEntries) {
    const std::string name = kEmbeddedLibraryNames + entry.name;
    out.kinds.push_back(entry.kind);
    if (entry.kind == 't') {
      const ComponentType* type = library.FindComponent(name);
      if (type == nullptr) throw std::runtime_error("library entry " + name + " is not a component type");
      bytes += SerializeComponentType(*type);
    } else if (entry.kind == 'f') {
      const FunctionDecl* function = library.FindFunction(name);
      if (function == nullptr) throw std::runtime_error("library entry " + name + " is not a function");
      bytes += SerializeFunction(*function);
    }
    out.offsets.push_back(static_cast<uint32_t>(bytes.size()));
  }
  bytes += start;
  out.offsets.push_back(static_cast<uint32_t>(bytes.size()));
  return out;
}

const Library& BuiltinLibrary() {
  static Library* library = [] {
    auto* lib = new Library();
    // Connector types first: component types refer to them.
    const std::string_view start = CompiledEntry(kNumEntries);
    if (!start.empty()) {
      DeserializeRecordsAndConnectors(start, lib);
    } else {
      for (const EmbeddedFile& f : kEmbeddedLibraryFiles) {
        if (std::string(f.name) == "components/connectors.yaml") LoadLibraryString(f.text, f.name, lib);
      }
    }
    auto types = std::make_shared<BuiltinTypes>(lib, !start.empty());
    lib->SetLazyTypes(types);
    // A call to a library function in any text read from now on reads the functions first, so
    // that the parser checks its argument count.
    static const BuiltinTypes* functions = types.get();
    static Library* into = lib;
    SetLibraryFunctionReader([] { functions->ReadFunctions(into); });
    return lib;
  }();
  return *library;
}

}  // namespace momenta
