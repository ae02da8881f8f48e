// Reading model and library files: YAML that could mean two things (a key given twice, a second
// document), files with nothing in them, YAML nested too deeply, names the expression language
// cannot refer to, and parse errors in a component's parameter named by the component and
// parameter. Each error is checked by its text, with both places for a duplicate.

#include <gtest/gtest.h>

#include <string>

#include "core/model_spec.h"

namespace momenta {
namespace {

std::string LoadError(const std::string& yaml) {
  try {
    LoadModelString(yaml, "test.yaml");
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

std::string LibraryError(const std::string& yaml) {
  Library library;
  try {
    LoadLibraryString(yaml, "lib.yaml", &library);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(YamlLoaderTest, SecondExperimentAtTopLevelNamesBothLines) {
  std::string msg = LoadError(R"(model: Twice
components:
  a: {type: Mass}
experiment: {stop: 1}
outputs: [a.s]
experiment: {stop: 2}
)");
  EXPECT_EQ(msg,
            "test.yaml:6:1: 'experiment' is given twice in the model file (first at line 4, column 1); "
            "remove one of them");
}

TEST(YamlLoaderTest, SecondOutputsAtTopLevel) {
  std::string msg = LoadError("model: Twice\noutputs: [a.s]\ncomponents: {a: {type: Mass}}\noutputs: [a.v]\n");
  EXPECT_NE(msg.find("test.yaml:4:1: 'outputs' is given twice in the model file (first at line 2, column 1)"),
            std::string::npos)
      << msg;
}

TEST(YamlLoaderTest, ParameterGivenTwiceInOneComponent) {
  std::string msg = LoadError(R"(model: Twice
components:
  s: {type: Sine, amplitude: 1, amplitude: 100}
)");
  EXPECT_EQ(msg,
            "test.yaml:3:33: 'amplitude' is given twice in components.s (first at line 3, column 19); "
            "remove one of them");
}

TEST(YamlLoaderTest, DuplicateInsideDefineAndInListItems) {
  std::string msg = LoadError(R"(model: Twice
define:
  Thing:
    variables:
      x: {start: 0}
      y: {start: 1}
      x: {start: 2}
    equations: [der(x) = -x, y = x]
components:
  t: {type: Thing}
)");
  EXPECT_NE(msg.find("test.yaml:7:7: 'x' is given twice in define.Thing.variables (first at line 5, column 7)"),
            std::string::npos)
      << msg;
  msg = LoadError(R"(model: Twice
components:
  a: {type: Mass}
  b: {type: Mass}
connections:
  - {connect: [a.flange_b, b.flange_a], connect: [a.flange_a, b.flange_b]}
)");
  EXPECT_NE(msg.find("test.yaml:6:41: 'connect' is given twice in connections[1] (first at line 6, column 6)"),
            std::string::npos)
      << msg;
}

TEST(YamlLoaderTest, QuotedAndPlainKeysAreTheSameKey) {
  std::string msg = LoadError("model: Q\n\"model\": R\n");
  EXPECT_NE(msg.find("test.yaml:2:1: 'model' is given twice in the model file (first at line 1, column 1)"),
            std::string::npos)
      << msg;
}

TEST(YamlLoaderTest, DuplicateInLibraryFile) {
  std::string msg = LibraryError(R"(Thing:
  parameters:
    k: {value: 1}
    k: {value: 2}
  variables: {x: {start: 0}}
  equations: [der(x) = -k*x]
)");
  EXPECT_NE(msg.find("lib.yaml:4:5: 'k' is given twice in Thing.parameters (first at line 3, column 5)"),
            std::string::npos)
      << msg;
  msg = LibraryError("A: {doc: one}\nA: {doc: two}\n");
  EXPECT_NE(msg.find("lib.yaml:2:1: 'A' is given twice in the library file (first at line 1, column 1)"),
            std::string::npos)
      << msg;
}

TEST(YamlLoaderTest, AliasedNodesAreCheckedOnceAndStillLoad) {
  // The same mapping reached through two aliases is not a duplicate of itself.
  ModelSpec spec = LoadModelString(R"(model: Aliases
components:
  a: &mass {type: Mass, m: 2}
  b: *mass
outputs: [a.s, b.s]
)",
                                   "test.yaml");
  ASSERT_EQ(spec.components.size(), 2u);
  EXPECT_EQ(spec.components[1].type, "Mass");
}

TEST(YamlLoaderTest, SecondDocumentIsAnError) {
  std::string msg = LoadError("model: One\ncomponents: {a: {type: Mass}}\n---\nmodel: Two\n");
  EXPECT_EQ(msg, "test.yaml:3:1: a second YAML document starts here; a model file holds one document");
  // An empty second document too; a leading '---' and a closing '...' are one document.
  msg = LoadError("---\nmodel: One\n---\n");
  EXPECT_NE(msg.find("test.yaml:3:1: a second YAML document"), std::string::npos) << msg;
  EXPECT_EQ(LoadError("---\nmodel: One\n...\n"), "");
}

TEST(YamlLoaderTest, StrayCommaIsASyntaxErrorNotAnEndlessStream) {
  // Found by fuzzing: yaml-cpp's LoadAll loops for ever, allocating, on ',' where a document
  // starts; Load reads it as an empty document.
  EXPECT_EQ(LoadError(","), "test.yaml:1:1: YAML syntax error: unexpected ','");
  EXPECT_EQ(LoadError(",\x95"), "test.yaml:1:1: YAML syntax error: unexpected ','");
  EXPECT_EQ(LoadError("model: A\n...\n,\n"), "test.yaml:3:1: a second YAML document starts here; a model file holds one document");
}

TEST(YamlLoaderTest, EmptyFile) {
  EXPECT_EQ(LoadError(""), "test.yaml: the model file is empty");
  EXPECT_EQ(LoadError("\n  \n"), "test.yaml: the model file is empty");
  EXPECT_EQ(LoadError("# only a comment\n"), "test.yaml: the model file is empty (it holds only comments)");
  EXPECT_EQ(LibraryError(""), "lib.yaml: the library file is empty");
}

TEST(YamlLoaderTest, DeeplyNestedYaml) {
  std::string deep = "model: Deep\ndoc: " + std::string(1000, '[') + std::string(1000, ']') + "\n";
  std::string msg = LoadError(deep);
  EXPECT_NE(msg.find("test.yaml:2:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("YAML nested too deeply: lists and mappings nested hundreds of levels deep are not "
                     "read (a model file needs a few levels)"),
            std::string::npos)
      << msg;
  EXPECT_EQ(msg.find("bad file"), std::string::npos) << msg;
  // Block mappings nested 1000 deep.
  std::string block = "model: Deep\ndoc:";
  for (int k = 0; k < 1000; ++k) block += "\n" + std::string(k + 1, ' ') + "a" + std::to_string(k) + ":";
  block += " 1\n";
  msg = LoadError(block);
  EXPECT_NE(msg.find("YAML nested too deeply"), std::string::npos) << msg;
}

TEST(YamlLoaderTest, ComponentNameThatIsNotAName) {
  std::string msg = LoadError("model: U\ncomponents:\n  \xc3\xbc: {type: Mass}\n");
  EXPECT_EQ(msg,
            "test.yaml:3:3: component '\xc3\xbc' is not a name: use ASCII letters, digits and '_', "
            "not starting with a digit");
  msg = LoadError("model: U\nparameters: {2k: 1}\n");
  EXPECT_NE(msg.find("test.yaml:2:14: parameter '2k' is not a name"), std::string::npos) << msg;
}

TEST(YamlLoaderTest, NonAsciiCharacterInAnExpressionIsQuotedWhole) {
  std::string msg = LoadError("model: U\ncomponents: {a: {type: Mass}}\noutputs: [\xc3\xbc.s]\n");
  EXPECT_EQ(msg, "test.yaml:3:11: unexpected character '\xc3\xbc' (U+00FC)");
  // Three and four bytes, and a byte that starts no UTF-8 character.
  msg = LoadError("model: U\noutputs: [\"a \xe2\x88\x92 b\"]\n");
  EXPECT_NE(msg.find("unexpected character '\xe2\x88\x92' (U+2212)"), std::string::npos) << msg;
  msg = LoadError("model: U\noutputs: [\"\xf0\x9f\x98\x80\"]\n");
  EXPECT_NE(msg.find("unexpected character '\xf0\x9f\x98\x80' (U+1F600)"), std::string::npos) << msg;
  msg = LoadError("model: U\noutputs: [\"a\xc3\"]\n");
  EXPECT_NE(msg.find("unexpected character byte 0xC3 (not UTF-8 text)"), std::string::npos) << msg;
}

TEST(YamlLoaderTest, ParseErrorInParameterNamesComponentAndParameter) {
  std::string msg = LoadError(R"(model: P
parameters: {k: 1}
components:
  spring: {type: Spring, c: k *}
)");
  EXPECT_EQ(msg, "test.yaml:4:32: expected a number, a name, '(' or '[', found end of text in 'k *' (in spring.c)");
  msg = LoadError("model: P\nparameters:\n  k: {value: 2 +* 3}\n");
  EXPECT_NE(msg.find("test.yaml:3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(in the value of P.k)"), std::string::npos) << msg;
  msg = LoadError("model: P\ncomponents:\n  m: {type: Mass, s: {start: \"1 +\"}}\n");
  EXPECT_NE(msg.find("(in the start of m.s)"), std::string::npos) << msg;
}

}  // namespace
}  // namespace momenta
