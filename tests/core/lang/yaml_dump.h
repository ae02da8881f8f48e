#pragma once
// Helpers of the YAML reader tests (yaml_tree_test, yaml_fast_test, yaml_event_readers_test,
// yaml_document_test): a document printed as text, node by node (kind, tag, text, line and
// column), so that two readers' documents compare as strings; the source tree's YAML files; a
// large written-out model.

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/exceptions.h>

#include "core/lang/yaml_document.h"
#include "core/lang/yaml_fast.h"
#include "core/lang/yaml_tree.h"

namespace momenta::testing {

/// Node `n` and the nodes below it, a line each (place, kind, tag, text), indented by depth.
inline void Dump(const YamlNode& n, int depth, std::ostringstream* o) {
  const YamlMark m = n.Mark();
  *o << std::string(2 * depth, ' ') << m.line << ":" << m.column << " ";
  if (n.IsNull()) {
    *o << "null\n";
  } else if (n.IsScalar()) {
    *o << "scalar " << n.Tag() << " '" << n.Scalar() << "'\n";
  } else if (n.IsSequence()) {
    *o << "seq " << n.Tag() << " " << n.size() << "\n";
    for (const auto& e : n) Dump(e, depth + 1, o);
  } else {
    *o << "map " << n.Tag() << " " << n.size() << "\n";
    for (auto it = n.begin(); it != n.end(); ++it) {
      Dump(it->first, depth + 1, o);
      Dump(it->second, depth + 2, o);
    }
  }
}

/// The document as text, or "error: …" with yaml-cpp's message when it cannot be read.
inline std::string Read(const std::string& text, YamlReader reader) {
  try {
    ParsedYaml p = ParseYamlDocument(text, reader);
    std::ostringstream o;
    o << p.documents << " documents";
    if (p.documents == 2) o << ", second at " << p.second_mark.line << ":" << p.second_mark.column;
    o << "\n";
    if (p.doc && !p.doc->empty()) Dump(p.doc->root(), 0, &o);
    return o.str();
  } catch (const YAML::Exception& e) {
    return "error: " + std::string(e.what());
  }
}

inline std::string FileText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The document the subset reader builds, in Read's words, or "refused".
inline std::string ReadSubset(const std::string& text) {
  std::unique_ptr<YamlDoc> doc = ParseYamlSubset(text);
  if (!doc) return "refused";
  std::ostringstream o;
  o << "1 documents\n";
  Dump(doc->root(), 0, &o);
  return o.str();
}

/// Every .yaml file under the source folders the tests and benchmarks use.
inline std::vector<std::filesystem::path> YamlFiles() {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (const char* dir : {"models", "components", "tests/data", "bench"}) {
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(MOMENTA_SOURCE_DIR) / dir)) {
      if (entry.path().extension() == ".yaml") files.push_back(entry.path());
    }
  }
  return files;
}

/// A chain written out, large enough that the automatic choice reads it with libyaml.
inline std::string LargeModel() {
  std::ostringstream y;
  y << "model: Big\ncomponents:\n  wall: {type: Fixed, s0: 0}\n";
  const int n = 3000;
  for (int i = 1; i <= n; ++i) {
    y << "  sd" << i << ": {type: SpringDamper, c: 1e4, d: 10, s_rel0: 1}\n";
    y << "  mass" << i << ": {type: Mass, m: 1, L: 0, s: {start: " << i << ", fixed: true}, v: {start: 0, fixed: true}}\n";
  }
  y << "connections:\n  - [wall.flange, sd1.flange_a]\n";
  for (int i = 1; i <= n; ++i) {
    y << "  - [sd" << i << ".flange_b, mass" << i << ".flange_a]\n";
    if (i < n) y << "  - [mass" << i << ".flange_b, sd" << i + 1 << ".flange_a]\n";
  }
  y << "outputs: [mass" << n << ".s]\n";
  return y.str();
}

}  // namespace momenta::testing
