// The event-parser readers (core/lang/yaml_event_readers.h): libyaml's reader must give the
// document yaml-cpp's gives (every node's kind, tag, text, line and column), on every model,
// library and test data file and on YAML written to probe the differences; and yaml-cpp's message
// wherever libyaml cannot read the text.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/lang/yaml_document.h"
#include "tests/core/lang/yaml_dump.h"

namespace momenta {
namespace {

using testing::FileText;
using testing::Read;

TEST(YamlEventReadersTest, LibyamlReadsEveryModelAndLibraryFileAsYamlCppDoes) {
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

TEST(YamlEventReadersTest, LibyamlAgreesOnProbes) {
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

}  // namespace
}  // namespace momenta
