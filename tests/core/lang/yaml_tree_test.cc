// The YAML document tree (core/lang/yaml_tree.h) and its readers (core/lang/yaml_document.h): the
// subset reader (core/lang/yaml_fast.h) and libyaml's reader must give the document yaml-cpp's event
// parser gives (every node's kind, tag, text, line and column), on every model, library and test data file, on YAML written to probe the
// differences and on random documents; and yaml-cpp's message wherever they cannot read the text.

#include <gtest/gtest.h>
#include <yaml-cpp/exceptions.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/lang/model_spec.h"
#include "core/lang/yaml_document.h"
#include "core/lang/yaml_fast.h"
#include "core/lang/yaml_tree.h"
#include "core/lang/yaml_loader.h"

namespace momenta {
namespace {

void Dump(const YamlNode& n, int depth, std::ostringstream* o) {
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

// ---- the subset reader (core/lang/yaml_fast.h) ------------------------------------------------------

/// The document the subset reader builds, in Read's words, or "refused".
std::string ReadSubset(const std::string& text) {
  std::unique_ptr<YamlDoc> doc = ParseYamlSubset(text);
  if (!doc) return "refused";
  std::ostringstream o;
  o << "1 documents\n";
  Dump(doc->root(), 0, &o);
  return o.str();
}

/// Every .yaml file under the source folders the tests and benchmarks use.
std::vector<std::filesystem::path> YamlFiles() {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (const char* dir : {"models", "components", "tests/data", "bench"}) {
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(MOMENTA_SOURCE_DIR) / dir)) {
      if (entry.path().extension() == ".yaml") files.push_back(entry.path());
    }
  }
  return files;
}

TEST(YamlTreeTest, SubsetReaderReadsEveryModelAndLibraryFileAsYamlCppDoesOrRefuses) {
  size_t files = 0, accepted = 0;
  for (const auto& path : YamlFiles()) {
    const std::string text = FileText(path);
    const std::string subset = ReadSubset(text);
    if (subset != "refused") {
      EXPECT_EQ(subset, Read(text, YamlReader::kYamlCpp)) << path;
      ++accepted;
    }
    // Refused or not, the automatic choice reads what yaml-cpp reads.
    EXPECT_EQ(Read(text, YamlReader::kAuto), Read(text, YamlReader::kYamlCpp)) << path;
    ++files;
  }
  EXPECT_GT(files, 20u);
  // The hand-written models open with a folded `doc: >-` (refused); library files without one,
  // and every written-out model, are read.
  EXPECT_GE(accepted, 1u);
  const std::string large = LargeModel();
  EXPECT_EQ(ReadSubset(large), Read(large, YamlReader::kYamlCpp));
}

TEST(YamlTreeTest, SubsetReaderAgreesOnProbesInsideTheSubset) {
  const std::vector<std::string> probes = {
      // Block mappings and sequences, nested; a sequence at its key's indentation; compact items.
      "a: 1\nb:\n  c: 2\n  d:\n    - x\n    - y\ne: 3\n",
      "a:\n- x\n- y\nb: 1\n",
      "- a: 1\n  b: 2\n- - 5\n  - 6\n- x\n",
      "  indented: 1\n  root: 2\n",
      "-1\n",
      "plain text at the root\n",
      "[a, b]\n",
      // Flow collections on one line, nested, empty, spaces around.
      "a: [1, [2, 3], {x: 4}]\nb: {p: {q: [r]}}\nc: []\nd: {}\ne: [ x ,y ]\nf: { k : v }\n",
      "c: {type: SpringDamper, s: {start: 1, fixed: true}}\n",
      // Scalars: plain with inner spaces, colons, hashes, quotes and brackets in block context.
      "a: x y  z\nb: http://host:80/p\nc: a#b\nd: it's\ne: f(x, y) [1] {2}\nf: -x\ng: a:b\n",
      // Quoted scalars, quoted keys, escapes, quoted look-alikes of nulls.
      "'a': 'it''s'\n\"b\": \"p\\tq \\\"r\\\" \\\\ \\/\"\nc: ''\nd: \"\"\ne: 'null'\nf: \"~\"\n",
      "{'a': x, \"b\": 'y'}\n",
      // Nulls.
      "a: ~\nb: null\nc: Null\nd: NULL\ne: nul\n~: 1\n",
      "a:\nb: 1\n",
      "a:\n  b:\n  c: 1\nd: 2\n",
      // Comments everywhere, blank lines, no final line break.
      "# head\n\na: 1 # c\n  # inner\nb: # c\n  - x # c\n\n  # c\n  - y\n# tail\n",
      "a: [x, y] # c\nb: 'q' # c\nc: 1",
      // UTF-8 (and bytes that are not) in scalars and comments: bytes, columns counted in bytes.
      "a: caf\xC3\xA9 # m/s\xC2\xB2\nb: [\xC2\xB0" "C, 'x\xE2\x80\xA8y']\nc: \xFF\xC3\nd: \xEF\xBB\xBF\n",
      // Flow collections over several lines, broken between entries; block scalars.
      "a: [1, 2,\n  3, [4,\n    5]\n  ]\nb: {x: 1, # c\n    y: [z]}\n",
      "a: >-\n  folded\n  text\n\n  kept\nb: |\n  one\n  two\n\n# c\nc: 1\n",
      "- |-\n  item # not a comment\n- x\n",
      // A key given twice (the loader reports it).
      "a: 1\nb: 2\na: 3\n",
      "{a: 1, a: 2}\n",
  };
  for (const std::string& text : probes) {
    EXPECT_EQ(ReadSubset(text), Read(text, YamlReader::kYamlCpp)) << "text:\n" << text;
  }
}

TEST(YamlTreeTest, SubsetReaderRefusesWhatItDoesNotReadAndYamlCppReadsIt) {
  const std::vector<std::string> probes = {
      // Anchors, aliases, tags, block scalars, complex keys.
      "a: &x 1\nb: *x\n", "a: !!str 12\n", "a: ! x\n", "? a\n: 1\n",
      // Block scalars with an indentation indicator, kept final lines, more indented lines, a
      // '#' line as indented as the text, no text; a block scalar at the root.
      "a: |2\n   one\n", "a: >+\n  one\n\n", "a: >\n  one\n    two\n", "a: |\n  one\n  # two\n",
      "a: |\nb: 1\n", "|\n  one\n", "a: |\n  one",
      // Documents and directives.
      "---\na: 1\n", "a: 1\n...\n", "a: 1\n---\nb: 2\n", "%YAML 1.2\n---\na: 1\n", "", "# only\n",
      // Values over several lines.
      "a: [1\n  2]\n", "a: {b:\n  1}\n", "a: [1,\n2]\n", "a: plain\n  continued\n",
      "a: 'two\n  lines'\n", "a: [x y,\n  z]\n" "b: [x\n  y]\n",
      // Empty values where the subset does not say where yaml-cpp marks them.
      "a: 1\nb:\n", "a:\n  b:\n", "- \n- x\n", "[a, , b]\n", "a: [x, ]\n", "{a: , b: 1}\n",
      "{a}\n", "[a: 1]\n",
      // Escapes of non-ASCII characters, a line continuation; bytes outside printable ASCII.
      "a: \"\\x41\"\n", "a: \"\\u00e9\"\n", "a: \"x\\\n  y\"\n",
      "a:\tb\n", "a: 1\r\nb: 2\r\n", "\xEF\xBB\xBF" "a: 1\n", std::string("a: \0\n", 5),
      "a: \x7F\n",
      // Flow scalars with characters yaml-cpp may read otherwise; a ':' or '#' in a flow scalar.
      "[a:b]\n", "[a#b]\n", "{a:b: 1}\n", "{\"a\":1}\n",
      // Errors.
      "a: {b: 1}}\n", "a: [1, 2\n", "a: 'open\n", "  a: 1\n b: 2\n", "a: b: c\n", ",\n",
      "a: 1\n  b: 2\n", "a: - x\n", "a: 1\n- x\n", "'a'#c\n", "[a] b\n", "[a]: b\n",
      // Deep nesting.
      std::string(300, '[') + std::string(300, ']') + "\n",
  };
  for (const std::string& text : probes) {
    EXPECT_EQ(ReadSubset(text), "refused") << "text:\n" << text;
    EXPECT_EQ(Read(text, YamlReader::kSubset), Read(text, YamlReader::kYamlCpp)) << "text:\n" << text;
  }
}

/// Random documents from the subset's pieces and from pieces around it (anchors, tags, block
/// scalars, empty values, stray lines, bad indentation), for SubsetReaderAgreesOnRandomDocuments.
class RandomYaml {
 public:
  explicit RandomYaml(unsigned seed) : rng_(seed) {}

  std::string Document() {
    std::string doc;
    Block(0, 0, false, &doc);
    if (Below(5) == 0) doc.pop_back();  // no final line break
    return doc;
  }

 private:
  int Below(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  template <size_t N>
  const char* Pick(const char* const (&choices)[N]) {
    return choices[Below(static_cast<int>(N))];
  }

  std::string Scalar() {
    static const char* const kPlain[] = {"a", "x1", "-1", "1e4", "3.5", "~", "null", "Null", "NULL",
                                         "true", "sd1.flange_a", "a b", "a  b", "-x", "nul", ".inf",
                                         "v", "w", "12", "0.5", "m s",
                                         // UTF-8, NEL, LS, a byte-order mark, bytes that are not
                                         // UTF-8.
                                         "m/s\xC2\xB2", "caf\xC3\xA9" " x", "a\xC2\x85" "b",
                                         "a\xE2\x80\xA8" "b", "\xEF\xBB\xBF" "x", "\xFF", "\xC3"};
    static const char* const kQuoted[] = {"'q'", "'it''s'", "''", "'a b'", "\"d\"", "\"a\\nb\"",
                                          "\"\\\"\"", "\"\"", "\"\\x41\"", "'#'", "\"a\\\\b\"",
                                          "'null'", "\"~\"", "' x '"};
    static const char* const kOdd[] = {"a:b", "a#b", "a #b", "it's", "x\"y", "a!b", "a&b", "a*b",
                                       "a|b", "a>b", "a%b", "a@b", "a`b", "a?b", "a-b", "f(x, y)",
                                       "a[1]", "a{b}", "a, b", "a]", "a}"};
    static const char* const kOutside[] = {"&x a", "*x", "!t a", "!!str 1", "|", ">", "? a", "%x",
                                           "@x", "`x", "- a", ":a", "?a", ",a", "-", "#c"};
    switch (Below(6)) {
      case 0: return Pick(kQuoted);
      case 1: return Pick(kOdd);
      case 2: return Pick(kOutside);
      default: return Pick(kPlain);
    }
  }

  std::string Flow(int depth) {
    if (depth > 2 || Below(3) == 0) return Scalar();
    // Entries also broken over lines, at indentations the enclosing block may or may not allow.
    static const char* const kComma[] = {", ", ",", " , ", ",\n    ", ",\n ", "\n  , ", ",\n",
                                         ", # c\n   "};
    static const char* const kColon[] = {": ", ": ", ":", " : "};
    const int n = Below(4);
    std::string s;
    if (Below(2)) {
      static const char* const kClose[] = {"]", "]", " ]", "\n  ]", "\n]"};
      s = Below(4) ? "[" : "[\n   ";
      for (int i = 0; i < n; ++i) s += (i ? Pick(kComma) : "") + Flow(depth + 1);
      if (Below(10) == 0) s += ", ";
      return s + Pick(kClose);
    }
    static const char* const kClose[] = {"}", "}", " }", "\n  }"};
    s = Below(4) ? "{" : "{\n   ";
    for (int i = 0; i < n; ++i) s += (i ? Pick(kComma) : "") + Scalar() + Pick(kColon) + Flow(depth + 1);
    return s + Pick(kClose);
  }

  std::string Comment() {
    static const char* const kComments[] = {" # c", "  #c", "#c", " #", " # \xC2\xB2", " # \xE2\x80\xA8"};
    return Below(6) == 0 ? Pick(kComments) : "";
  }

  /// A literal or folded block scalar after `key:`, its lines mostly at one indentation.
  void Text(int indent, std::string* out) {
    static const char* const kHeaders[] = {" >-", " |", " >", " |-", " >+", " |2", " > # c", " |#c"};
    static const char* const kLines[] = {"text", "a b", "x: y", "# hash", "- item", "'q'", "a  ",
                                         "m/s\xC2\xB2", "a\xC2\x85" "b"};
    static const int kShift[] = {2, 2, 2, 2, 1, 3, 0, 4};
    *out += std::string(Pick(kHeaders)) + "\n";
    const int n = Below(5);
    for (int i = 0; i < n; ++i) {
      const int r = Below(8);
      if (r == 0) {
        *out += std::string(static_cast<size_t>(Below(6)), ' ') + "\n";  // an empty line
      } else {
        *out += std::string(static_cast<size_t>(indent + kShift[Below(8)]), ' ') + Pick(kLines) + "\n";
      }
    }
  }

  void Value(int indent, int depth, std::string* out) {
    const int r = Below(depth > 3 ? 5 : 12);
    if (r >= 10) {
      Text(indent, out);
    } else if (r < 3) {
      *out += " " + Scalar() + Comment() + "\n";
    } else if (r < 5) {
      *out += " " + Flow(0) + Comment() + "\n";
    } else if (r == 5) {
      *out += Comment() + "\n";  // an empty value
    } else {
      static const char* const kBetween[] = {"\n", "# c\n", "  # c\n"};
      static const int kStep[] = {2, 2, 4, 1, 0};
      *out += Comment() + "\n";
      if (Below(8) == 0) *out += Pick(kBetween);
      Block(indent + kStep[Below(5)], depth + 1, false, out);
    }
  }

  void Block(int indent, int depth, bool inline_start, std::string* out) {
    static const char* const kStray[] = {"\n", "# c\n", " # c\n", "   # c\n", "  more\n", "---\n",
                                         "...\n", "\t\n", "a: b: c\n", "- x\n"};
    const int n = 1 + Below(4);
    const bool sequence = Below(3) == 0;
    for (int i = 0; i < n; ++i) {
      if (!(inline_start && i == 0)) {
        const int off = Below(30) == 0 ? (Below(2) ? 1 : -1) : 0;
        *out += std::string(static_cast<size_t>(std::max(indent + off, 0)), ' ');
      }
      if (sequence) {
        *out += "-";
        const int r = Below(6);
        if (r == 0 && depth < 4) {
          *out += " ";
          Block(indent + 2, depth + 1, true, out);
        } else if (r == 1 && depth < 4) {
          *out += Comment() + "\n";
          Block(indent + 2, depth + 1, false, out);
        } else if (r == 2) {
          *out += Comment() + "\n";
        } else {
          *out += " " + (Below(2) ? Scalar() : Flow(0)) + Comment() + "\n";
        }
      } else {
        *out += Scalar() + (Below(4) ? ":" : " :");
        Value(indent, depth, out);
      }
      if (Below(15) == 0) *out += Pick(kStray);
    }
  }

  std::mt19937 rng_;
};

TEST(YamlTreeTest, SubsetReaderAgreesOnRandomDocuments) {
  RandomYaml random(12);
  int accepted = 0;
  for (int k = 0; k < 10000; ++k) {
    const std::string text = random.Document();
    const std::string subset = ReadSubset(text);
    if (subset == "refused") continue;
    ++accepted;
    ASSERT_EQ(subset, Read(text, YamlReader::kYamlCpp)) << "text:\n" << text;
  }
  // Enough of them inside the subset for the comparison to mean something.
  EXPECT_GT(accepted, 800) << accepted;
}

TEST(YamlTreeTest, LargeFileOutsideTheSubsetLoadsTheSame) {
  // Each construct the subset reader refuses, deep in a large file: libyaml or yaml-cpp reads it.
  const std::vector<std::pair<std::string, std::string>> edits = {
      {"  sd1: {type: SpringDamper, c: 1e4, d: 10, s_rel0: 1}\n",
       "  sd1: &sd {type: SpringDamper, c: 1e4, d: 10, s_rel0: 1}\n"},
      {"  sd2: {type: SpringDamper, c: 1e4, d: 10, s_rel0: 1}\n",
       "  sd2: {type: SpringDamper, c: !!str 1e4, d: 10,\n        s_rel0: 1}\n"},
      {"model: Big\n", "model: Big\ndoc: |+\n  A chain\n  written out.\n\n"},
      {"  sd3: {type: SpringDamper, c: 1e4, d: 10, s_rel0: 1}\n",
       "  sd3: {type: SpringDamper, c: 1e4, d: 10, s_rel0:\n    1}\n"},
      {"model: Big\n", "--- \nmodel: Big\n"},
      {"model: Big\n", "model: \"B\\x69g\"\n"},
  };
  const std::string large = LargeModel();
  for (const auto& [from, to] : edits) {
    std::string text = large;
    text.replace(text.find(from), from.size(), to);
    ASSERT_TRUE(ParseYamlSubset(text) == nullptr) << to;
    EXPECT_EQ(Read(text, YamlReader::kAuto), Read(text, YamlReader::kYamlCpp)) << to;
    const ModelSpec spec = LoadModelString(text, "big.yaml");
    EXPECT_EQ(spec.components.size(), 6001u) << to;
    EXPECT_EQ(spec.name, "Big") << to;
  }
}

TEST(YamlTreeTest, LargeFileModelErrorsNameTheirLine) {
  // A bad value in the 3000th mass of a file the subset reader reads: the message names its line
  // and column.
  std::string text = LargeModel();
  const std::string from = "  mass3000: {type: Mass, m: 1, L: 0, s: {start: 3000, fixed: true}";
  const std::string to = "  mass3000: {type: Mass, m: 1, L: 0, s: {start: 3000, fixed: maybe}";
  text.replace(text.find(from), from.size(), to);
  ASSERT_NE(ReadSubset(text), "refused");
  std::string message;
  try {
    LoadModelString(text, "big.yaml");
  } catch (const ModelError& e) {
    message = e.what();
  }
  const std::string place = "big.yaml:6003:" + std::to_string(to.find("maybe") + 1) + ": ";
  EXPECT_EQ(message, place + "mass3000.s.fixed must be true or false, found 'maybe'");
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
  EXPECT_EQ(root["c"][0].AsText(), "x");
  EXPECT_EQ(root["d"].AsText(), "null");
  EXPECT_THROW(root["c"].AsText(), YAML::BadConversion);
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
