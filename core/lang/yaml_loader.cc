// Reading model and library files (core/lang/yaml_loader.h): a file's document
// (yaml_loader_document.h), its model or library entries (yaml_loader_model.h,
// yaml_loader_types.h), and the files its `uses:` names, each read once. Every error names the
// file, line and column, the user's path, what was expected, and the valid keys.

#include "core/lang/yaml_loader.h"

#include <yaml-cpp/exceptions.h>

#include <filesystem>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "core/base/limits.h"
#include "core/lang/arrays.h"
#include "core/lang/yaml_loader_document.h"
#include "core/lang/yaml_loader_model.h"
#include "core/lang/yaml_loader_types.h"
#include "core/lang/yaml_loader_values.h"

namespace momenta {

namespace {

ModelSpec ParseModel(const std::string& yaml, const std::string& file_name) {
  ValueReader reader(file_name);
  std::unique_ptr<YamlDoc> doc = ParseYamlFile(yaml, file_name, "model file");
  try {
    return ReadModel(reader, doc->root());
  } catch (const YAML::Exception& e) {
    throw ModelError(MarkLoc(file_name, e.mark.line, e.mark.column), "malformed model: " + e.msg);
  }
}

/// The file a `uses:` entry of `spec` names (relative to the directory of spec.file), as joined.
std::filesystem::path UsedPath(const ModelSpec& spec, const UsesSpec& u) {
  namespace fs = std::filesystem;
  fs::path path = fs::path(u.path).is_absolute() ? fs::path(u.path)
                                                 : fs::path(spec.file).parent_path() / u.path;
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    throw ModelError(u.loc, "uses: no file '" + u.path + "' (looked for " +
                                path.lexically_normal().string() + ")");
  }
  return path;
}

/// Appends to top->defines the types of every file top->uses names, and of the files those use,
/// each file once: a model file becomes a type of its model's name (after its own define: types
/// and the types of the files it uses), a library file gives its component types. The walk keeps
/// its own stack of files, as deep as the chain of files each using the next, which may be
/// kMaxNestingDepth long.
void LoadUses(ModelSpec* top, std::set<std::string>* loaded) {
  struct Open {
    ModelSpec spec;
    size_t next = 0;  ///< the next entry of spec.uses to read
  };
  std::vector<Open> chain;
  chain.push_back({std::move(*top), 0});
  while (true) {
    Open& at = chain.back();
    // A file whose entries are all read becomes a type of the file that uses it.
    if (at.next == at.spec.uses.size()) {
      if (chain.size() == 1) break;
      ModelSpec used = std::move(at.spec);
      chain.pop_back();
      ModelSpec& user = chain.back().spec;
      for (auto& d : used.defines) user.defines.push_back(std::move(d));
      user.own->AddOwnEntries(*used.own);
      user.defines.push_back(ModelAsType(used));
      continue;
    }
    const UsesSpec& u = at.spec.uses[at.next++];
    const std::filesystem::path path = UsedPath(at.spec, u);
    std::error_code ec;
    if (!loaded->insert(std::filesystem::weakly_canonical(path, ec).string()).second) continue;
    const std::string file = path.lexically_normal().string();
    std::string text;
    try {
      text = ReadModelText(file, "file in uses:");
    } catch (const ModelError& e) {
      throw ModelError(u.loc, std::string("uses: ") + e.what());
    }
    std::unique_ptr<YamlDoc> doc = ParseYamlFile(text, file, "file in uses:");
    const YamlNode root = doc->root();
    if (root.IsMap() && root["model"]) {
      if (chain.size() >= static_cast<size_t>(kMaxNestingDepth)) {
        throw ModelError(u.loc, "uses: " + NestedTooDeep("files") + ": '" + file + "' is file " +
                                    std::to_string(chain.size() + 1) + " of a chain of files " +
                                    "each using the next, from " + chain.front().spec.file);
      }
      chain.push_back({ParseModel(text, file), 0});
      continue;
    }
    try {
      ReadLibraryEntries(ValueReader(file), root, at.spec.own.get(), &at.spec.defines, true,
                         "a library file in uses:");
    } catch (const YAML::Exception& e) {
      throw ModelError(MarkLoc(file, e.mark.line, e.mark.column),
                       "malformed library file: " + e.msg);
    }
  }
  *top = std::move(chain.front().spec);
}

}  // namespace

ComponentType ModelAsType(const ModelSpec& m) {
  ComponentType t;
  t.name = m.name;
  t.doc = m.doc;
  t.parameters = m.parameters;
  t.variables = m.variables;
  t.equations = m.equations;
  t.initial_equations = m.initial_equations;
  t.whens = m.whens;
  t.components = m.components;
  t.connections = m.connections;
  t.loc = m.loc;
  t.user_defined = true;
  return t;
}

ModelSpec LoadModelString(const std::string& yaml, const std::string& file_name) {
  ModelSpec spec = ParseModel(yaml, file_name);
  if (!spec.uses.empty()) {
    std::set<std::string> loaded;
    std::error_code ec;
    loaded.insert(std::filesystem::weakly_canonical(file_name, ec).string());
    // The used types first, so that a clash is reported at the model's own definition.
    std::vector<ComponentType> own = std::move(spec.defines);
    spec.defines.clear();
    LoadUses(&spec, &loaded);
    for (auto& d : own) spec.defines.push_back(std::move(d));
  }
  return spec;
}

ModelSpec LoadModelFile(const std::string& path) {
  return LoadModelString(ReadModelText(path, "model file"), path);
}

void LoadLibraryString(const std::string& yaml, const std::string& file_name, Library* library) {
  ValueReader reader(file_name);
  std::unique_ptr<YamlDoc> doc = ParseYamlFile(yaml, file_name, "library file");
  ReadLibraryEntries(reader, doc->root(), library, nullptr, false);
  ScalariseLibrary(library);  // vectors and matrices become scalars (core/lang/arrays.h)
}

}  // namespace momenta
