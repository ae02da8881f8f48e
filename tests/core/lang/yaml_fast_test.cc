// The subset reader (core/lang/yaml_fast.h): on every model, library and test data file, on YAML
// written to probe the subset's edges and on random documents, it gives the document yaml-cpp's
// event parser gives (every node's kind, tag, text, line and column), or refuses the text.

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "core/lang/yaml_document.h"
#include "core/lang/yaml_fast.h"
#include "tests/core/lang/yaml_dump.h"

namespace momenta {
namespace {

using testing::FileText;
using testing::LargeModel;
using testing::Read;
using testing::ReadSubset;
using testing::YamlFiles;

TEST(YamlFastTest, SubsetReaderReadsEveryModelAndLibraryFileAsYamlCppDoesOrRefuses) {
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

TEST(YamlFastTest, SubsetReaderAgreesOnProbesInsideTheSubset) {
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

TEST(YamlFastTest, SubsetReaderRefusesWhatItDoesNotReadAndYamlCppReadsIt) {
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

TEST(YamlFastTest, SubsetReaderAgreesOnRandomDocuments) {
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

}  // namespace
}  // namespace momenta
