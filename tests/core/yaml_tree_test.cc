// The YAML document tree (core/yaml_tree.h): libyaml's reader, used for large files, must give the
// document yaml-cpp's event parser gives (every node's kind, tag, text, line and column), on every
// model, library and test data file and on YAML written to probe the differences; and yaml-cpp's
// message wherever libyaml cannot read the text.

#include <gtest/gtest.h>
#include <yaml-cpp/exceptions.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/model_spec.h"
#include "core/yaml_tree.h"

namespace momenta {
namespace {

void Dump(const YamlNode& n, int depth, std::ostringstream* o) {
  const YAML::Mark m = n.Mark();
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
std::string Read(const std::string& text, YamlReader reader) {
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

std::string FileText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(YamlTreeTest, LibyamlReadsEveryModelAndLibraryFileAsYamlCppDoes) {
  namespace fs = std::filesystem;
  const fs::path src = MOMENTA_SOURCE_DIR;
  size_t files = 0;
  for (const char* dir : {"models", "components", "tests/data", "bench"}) {
    for (const auto& entry : fs::recursive_directory_iterator(src / dir)) {
      if (entry.path().extension() != ".yaml") continue;
      const std::string text = FileText(entry.path());
      EXPECT_EQ(Read(text, YamlReader::kLibyaml), Read(text, YamlReader::kYamlCpp)) << entry.path();
      ++files;
    }
  }
  EXPECT_GT(files, 20u);
}

TEST(YamlTreeTest, LibyamlAgreesOnProbes) {
  const std::vector<std::string> probes = {
      // Nulls and empty values, quoted look-alikes.
      "a: 1\nb:\n",
      "a:\n  b:\nc: 1\n",
      "- \n- x\n-\n",
      "{a: , b: 1, c: }\n",
      "[a, , b]\n",
      "a: [x, ]\nb: &e\nc: *e\n",
      "a:\nb: ~\nc: null\nd: Null\ne: NULL\nf: 'null'\ng: \"~\"\nh: ''\n",
      // Scalar styles: quoted, block literal and folded, multi-line plain.
      "a: 'x y'\nb: \"p\\tq\"\nc: |\n  one\n  two\nd: >-\n  folded\n  text\ne: plain\n  continued\n",
      // Flow and block collections, nested; sequences of mappings.
      "a: [1, [2, 3], {x: 4}]\nb:\n  - x: 1\n    y: 2\n  - - 5\n    - 6\nc: {p: {q: [r]}}\n",
      // Anchors and aliases, explicit tags.
      "a: &x {k: 1}\nb: *x\nc: &s text\nd: *s\ne: !!str 12\nf: !custom v\ng: ! plain\n",
      // Keys: quoted and plain, complex.
      "\"a\": 1\n'b': 2\n? c\n: 3\n",
      // Comments, document markers, a second document.
      "# only\n---\na: 1\n...\n",
      "a: 1\n---\nb: 2\n",
      "",
      "# just a comment\n",
      "---\n",
      // Errors: libyaml cannot read these, so yaml-cpp's message is the answer.
      "a: {b: 1}}\n",
      "a: [1, 2\n",
      "a: *undefined\n",
      "a: 'open\n",
      "  a: 1\n b: 2\n",
      "a: b: c\n",
      ",\n",
      // Deep nesting.
      std::string(300, '[') + std::string(300, ']') + "\n",
      // Tabs, CRLF line ends, a byte-order mark.
      "a: 1\r\nb:\r\n  - x\r\n",
      "\xEF\xBB\xBF" "a: 1\n",
  };
  for (const std::string& text : probes) {
    EXPECT_EQ(Read(text, YamlReader::kLibyaml), Read(text, YamlReader::kYamlCpp)) << "text:\n" << text;
  }
}

/// A chain written out, large enough that the automatic choice reads it with libyaml.
std::string LargeModel() {
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

TEST(YamlTreeTest, LargeFileReadsTheSameEitherWay) {
  const std::string text = LargeModel();
  ASSERT_GE(text.size(), kLargeYamlBytes);
  EXPECT_EQ(Read(text, YamlReader::kAuto), Read(text, YamlReader::kYamlCpp));
  const ModelSpec spec = LoadModelString(text, "big.yaml");
  EXPECT_EQ(spec.components.size(), 6001u);
  EXPECT_EQ(spec.connections.size(), 6000u);
  EXPECT_EQ(spec.components.back().loc.line, 6003);
}

TEST(YamlTreeTest, LargeFileErrorsAreYamlCppsAtTheSamePlace) {
  std::string text = LargeModel();
  // A key given twice deep in the file, then a syntax error after it.
  const std::string dup = text + "outputs: [x]\n";
  std::string dup_message, bad_message;
  try {
    LoadModelString(dup, "big.yaml");
  } catch (const ModelError& e) {
    dup_message = e.what();
  }
  EXPECT_NE(dup_message.find("'outputs' is given twice"), std::string::npos) << dup_message;
  EXPECT_NE(dup_message.find("big.yaml:12006:1"), std::string::npos) << dup_message;
  const std::string bad = text + "experiment: {stop: 1}}\n";
  try {
    LoadModelString(bad, "big.yaml");
  } catch (const ModelError& e) {
    bad_message = e.what();
  }
  EXPECT_NE(bad_message.find("big.yaml:12006:22: YAML syntax error"), std::string::npos) << bad_message;
}

TEST(YamlTreeTest, NodeAnswersAsYamlCppNodes) {
  ParsedYaml p = ParseYamlDocument("a: {b: 1}\nc: [x, y]\nd:\n", YamlReader::kYamlCpp);
  const YamlNode root = p.doc->root();
  EXPECT_FALSE(root["missing"]);
  EXPECT_THROW(root["missing"].IsMap(), YAML::InvalidNode);
  EXPECT_THROW(root["a"]["b"]["z"], YAML::BadSubscript);
  EXPECT_EQ(root["c"][1].Scalar(), "y");
  EXPECT_FALSE(root["c"][2]);
  EXPECT_EQ(root["d"].as<std::string>(), "null");
  EXPECT_THROW(root["a"].as<std::string>(), YAML::BadConversion);
  EXPECT_EQ(root["a"].Scalar(), "");
  EXPECT_EQ(root["c"].size(), 2u);
  EXPECT_EQ(root.size(), 3u);
  // A missing key keeps its name for yaml-cpp's message (held once by the document).
  for (const char* key : {"missing", "other", "missing"}) {
    try {
      root[key].IsMap();
      ADD_FAILURE() << key;
    } catch (const YAML::InvalidNode& e) {
      EXPECT_EQ(std::string(e.what()), YAML::InvalidNode(key).what());
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace momenta
