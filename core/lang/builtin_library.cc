// The component library (components/*.yaml) compiled into the binary, so the CLI works from any
// folder. The build writes builtin_library_data.inc from the YAML files (see core/CMakeLists.txt).
//
// Reading all of it (some 120 types, 120 KB of YAML, their equations parsed) took about 10 ms of
// CPU, most of a small model's whole run, which uses a handful of types. So the records and the
// connector types are read at once, the functions together when a text first calls one or a
// lookup first asks for one (a fifth of the ball and pendulum's whole run when read at start),
// and each component type the first time a model names it (LazyTypes): at start
// the text is only cut into its top-level entries, one a type. An entry is read as its own YAML
// document, preceded by as many empty lines as come before it in its file, so that every location
// (file:line:col) is the one reading the whole file gives; each type is turned into its scalar
// form (core/lang/arrays.h) as it is read, which needs only the connector types. The library is
// one object for the process, never copied (a copy would share the record of what was read).

#include "core/lang/builtin_library.h"

#include <cstring>
#include <mutex>
#include <set>
#include <string_view>

#include "core/lang/arrays.h"
#include "core/lang/component_type.h"
#include "core/lang/model_spec.h"
#include "core/lang/parser.h"
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
#include "builtin_library_data.inc"

/// One top-level entry of a library file: a type's name and text.
struct Entry {
  const char* file;
  std::string_view text;
  size_t line = 1;  ///< the line of the file the text starts at
  bool read = false;
};

/// The entries of the embedded files other than the connectors, each read on first use.
class BuiltinTypes : public LazyTypes {
 public:
  /// Cuts every file but connectors.yaml into its entries; reads at once the records and the
  /// connector types (so that every connector type is known without a lookup). The functions are
  /// read together on first use (ReadFunctions): most models call none.
  explicit BuiltinTypes(Library* library) {
    for (const EmbeddedFile& f : kEmbeddedLibraryFiles) {
      if (std::strcmp(f.name, "components/connectors.yaml") != 0) Cut(f);
    }
    // Every function's name first, so that any text may call one before it is read.
    for (auto& [name, entry] : entries_) {
      if (IsFunction(entry)) RegisterFunction(name, -1);
    }
    // Records first: connector types use them.
    for (const bool first : {true, false}) {
      for (auto& [name, entry] : entries_) {
        if (entry.read || IsFunction(entry) || entry.text.find("\n  kind:") == std::string_view::npos) continue;
        if ((entry.text.find("\n  kind: record") != std::string_view::npos) == first) ReadEntry(&entry, library);
      }
    }
  }

  void ReadFunctions(Library* library) const override {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    if (functions_read_) return;
    functions_read_ = true;
    for (auto& [name, entry] : entries_) {
      if (!entry.read && IsFunction(entry)) ReadEntry(&entry, library);
    }
  }

  /// Reads the type named `name` and every type whose last dotted part is `name`: Library's
  /// short-name rule (a short name is ambiguous when two packages use it, and an unqualified type
  /// of that name comes first) then decides as it would in the whole library.
  void Read(const std::string& name, Library* library) const override {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    if (!asked_.insert(name).second) return;
    if (auto it = entries_.find(name); it != entries_.end() && !it->second.read) ReadEntry(&it->second, library);
    if (auto s = by_short_name_.find(name); s != by_short_name_.end()) {
      for (const std::string& full : s->second) {
        Entry& entry = entries_.at(full);
        if (!entry.read) ReadEntry(&entry, library);
      }
    }
  }

  void ReadAll(Library* library) const override {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    ReadFunctions(library);
    for (auto& [name, entry] : entries_) {
      if (!entry.read) ReadEntry(&entry, library);
    }
  }

 private:
  static bool IsFunction(const Entry& entry) {
    return entry.text.find("\n  kind: function") != std::string_view::npos;
  }

  /// Records the top-level entries of `f`: a line that starts with a letter starts one (keys are
  /// type names; comments, indented lines and blank lines belong to the entry above).
  void Cut(const EmbeddedFile& f) {
    const std::string_view text(f.text);
    Entry* open = nullptr;
    size_t line = 1;
    for (size_t at = 0; at < text.size(); ++line) {
      size_t end = text.find('\n', at);
      end = end == std::string_view::npos ? text.size() : end + 1;
      const char c = text[at];
      if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')) {
        if (open) open->text = text.substr(open->text.data() - text.data(), at - (open->text.data() - text.data()));
        const std::string name(text.substr(at, text.find(':', at) - at));
        open = &entries_[name];
        *open = Entry{f.name, text.substr(at), line, false};
        for (const std::string& tail : ShortNames(name)) by_short_name_[tail].push_back(name);
      }
      at = end;
    }
  }

  /// Reads one entry into `library`, in its scalar form.
  void ReadEntry(Entry* entry, Library* library) const {
    entry->read = true;
    std::string text(entry->line - 1, '\n');
    text += entry->text;
    const ValueReader reader(entry->file);
    std::unique_ptr<YamlDoc> doc = ParseYamlFile(text, entry->file, "library file");
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

  mutable std::map<std::string, Entry> entries_;
  /// Last dotted part -> the qualified names that end in it.
  std::map<std::string, std::vector<std::string>> by_short_name_;
  mutable std::set<std::string> asked_;  ///< names Read has resolved already
  mutable bool functions_read_ = false;
  mutable std::recursive_mutex mutex_;
};

}  // namespace

const Library& BuiltinLibrary() {
  static Library* library = [] {
    auto* lib = new Library();
    // Connector types first: component types refer to them.
    for (const EmbeddedFile& f : kEmbeddedLibraryFiles) {
      if (std::string(f.name) == "components/connectors.yaml") LoadLibraryString(f.text, f.name, lib);
    }
    auto types = std::make_shared<BuiltinTypes>(lib);
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
