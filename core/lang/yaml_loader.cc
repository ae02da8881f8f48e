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

/// Appends to spec->defines the types of every file spec->uses names (paths relative to the
/// directory of spec->file), and of the files those use, each file once: a model file becomes a
/// type of its model's name (with its own define: types), a library file gives its component types.
void LoadUses(ModelSpec* spec, std::set<std::string>* loaded) {
  namespace fs = std::filesystem;
  for (const UsesSpec& u : spec->uses) {
    fs::path path = fs::path(u.path).is_absolute() ? fs::path(u.path)
                                                   : fs::path(spec->file).parent_path() / u.path;
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      throw ModelError(u.loc, "uses: no file '" + u.path + "' (looked for " +
                                  path.lexically_normal().string() + ")");
    }
    std::string key = fs::weakly_canonical(path, ec).string();
    if (!loaded->insert(key).second) continue;
    std::string file = path.lexically_normal().string();
    std::string text;
    try {
      text = ReadModelText(file, "file in uses:");
    } catch (const ModelError& e) {
      throw ModelError(u.loc, std::string("uses: ") + e.what());
    }
    std::unique_ptr<YamlDoc> doc = ParseYamlFile(text, file, "file in uses:");
    const YamlNode root = doc->root();
    if (root.IsMap() && root["model"]) {
      ModelSpec used = ParseModel(text, file);
      LoadUses(&used, loaded);
      for (auto& d : used.defines) spec->defines.push_back(std::move(d));
      spec->defines.push_back(ModelAsType(used));
    } else {
      Library scratch;
      try {
        ReadLibraryEntries(ValueReader(file), root, &scratch, &spec->defines, true,
                           "a library file in uses:");
      } catch (const YAML::Exception& e) {
        throw ModelError(MarkLoc(file, e.mark.line, e.mark.column),
                         "malformed library file: " + e.msg);
      }
    }
  }
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
