// Reading model and library files: YAML that could mean two things (a key given twice, a second
// document), files with nothing in them, YAML nested too deeply, names the expression language
// cannot refer to, and parse errors in a component's parameter named by the component and
// parameter. Each error is checked by its text, with both places for a duplicate.

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "core/lang/model_spec.h"
#include "core/lang/yaml_document.h"
#include "core/lang/yaml_loader.h"

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

namespace momenta {
namespace {

/// A written-out chain of 60 masses whose 100th component, sd50, is written as `entry`.
std::string ChainWithEntry(const std::string& entry) {
  std::string y = "model: Big\ncomponents:\n  wall: {type: Fixed, s0: 0}\n";
  for (int i = 1; i <= 60; ++i) {
    y += i == 50
             ? entry
             : "  sd" + std::to_string(i) + ": {type: SpringDamper, c: 1e4, d: 10, s_rel0: 1}\n";
    y += "  mass" + std::to_string(i) +
         ": {type: Mass, m: 1, L: 0, s: {start: " + std::to_string(i) +
         ", fixed: true}, v: {start: 0, fixed: true}}\n";
  }
  return y + "connections:\n  - [wall.flange, sd1.flange_a]\n";
}

/// The message of loading `yaml` with each reader (core/lang/yaml_document.h), or "" when it loads.
std::string LoadErrorWith(const std::string& yaml, YamlReader reader) {
  SetDefaultYamlReader(reader);
  std::string message = LoadError(yaml);
  SetDefaultYamlReader(YamlReader::kAuto);
  return message;
}

// The descriptions of a component's values are put together only for a message (core/
// yaml_loader.cc, What); plain numbers and names skip the tokenizer (core/lang/parser.cc). The
// messages are those the loader gave before, on both readers.
TEST(YamlLoaderTest, ErrorInAModifierOfTheHundredthComponentNamesFileLineAndComponent) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"  sd50: {type: SpringDamper, c: 1e4 *, d: 10, s_rel0: 1}\n",
       "test.yaml:102:38: expected a number, a name, '(' or '[', found end of text in '1e4 *' (in "
       "sd50.c)"},
      {"  sd50: {type: SpringDamper, c: 1e4, d: 10, s_rel0: {start: 1 +, fixed: true}}\n",
       "test.yaml:102:64: expected a number, a name, '(' or '[', found end of text in '1 +' (in "
       "the start of "
       "sd50.s_rel0)"},
      {"  sd50: {type: SpringDamper, c: 1e4, d: 10, s_rel0: {start: 1, fixed: maybe}}\n",
       "test.yaml:102:71: sd50.s_rel0.fixed must be true or false, found 'maybe'"},
      {"  sd50: {type: SpringDamper, c: 1e4, d: 10, s_rel0: {begin: 1}}\n",
       "test.yaml:102:54: unknown key 'begin' in sd50.s_rel0 (valid keys: start, fixed, "
       "nominal, min, max, stateSelect)"},
      {"  sd50: {type: SpringDamper, c: 1e4, d: 10, s_rel0: {stateSelect: often}}\n",
       "test.yaml:102:67: unknown stateSelect 'often' for sd50.s_rel0 (valid choices: never, "
       "avoid, default, "
       "prefer, always)"},
      {"  sd50: {type: SpringDamper, c: .inf, d: 10, s_rel0: 1}\n",
       "test.yaml:102:33: sd50.c must be a finite number, found '.inf'"},
      {"  sd50: {type: SpringDamper, c: 1e4 kN/furlong, d: 10, s_rel0: 1}\n",
       "test.yaml:102:33: unit 'kN/furlong' does not parse: unknown unit 'furlong' at character 4 "
       "(write units "
       "as Modelica does: m/s2, N.m, kg.m2, 1/s, rad/s, degC), in the value of sd50.c"},
      {"  sd50: {type: SpringDamper, c: [], d: 10, s_rel0: 1}\n",
       "test.yaml:102:33: sd50.c is an empty list; an array has at least one element"},
      {"  sd50: {type: SpringDamper, c: 1e400, d: 10, s_rel0: 1}\n",
       "test.yaml:102:33: number out of range '1e400' (double's range: magnitudes from 2.2e-308 to 1.8e308) (in sd50.c)"},
      {"  sd50: {type: SpringDamper, [c]: 1e4}\n",
       "test.yaml:102:30: malformed model: bad conversion"},
      {"  sd49: {type: SpringDamper, c: 1e4, d: 10, s_rel0: 1}\n",
       "test.yaml:102:3: 'sd49' is given twice in components (first at line 100, column 3); remove "
       "one of them"},
      {"  sd50: {type: SpringDamper, c: 1e4, d: 10, c: 1}\n",
       "test.yaml:102:45: 'c' is given twice in components.sd50 (first at line 102, column 30); "
       "remove one of "
       "them"},
  };
  for (const auto& [entry, message] : cases) {
    const std::string yaml = ChainWithEntry(entry);
    EXPECT_EQ(LoadErrorWith(yaml, YamlReader::kSubset), message) << entry;
    EXPECT_EQ(LoadErrorWith(yaml, YamlReader::kLibyaml), message) << entry;
    EXPECT_EQ(LoadErrorWith(yaml, YamlReader::kYamlCpp), message) << entry;
  }
}

// Plain numbers and names go through the loader without the tokenizer: the same values as the
// parser's, with their units and places.
TEST(YamlLoaderTest, PlainValuesOfAWrittenOutModelReadAsTheParserReadsThem) {
  const ModelSpec spec =
      LoadModelString(ChainWithEntry("  sd50: {type: SpringDamper, c: 2.5e3, d: .5, s_rel0: 40 "
                                     "cm}\n"),
                      "test.yaml");
  const ComponentSpec& sd50 = spec.components[99];
  ASSERT_EQ(sd50.name, "sd50");
  ASSERT_EQ(sd50.modifiers.size(), 3u);
  EXPECT_EQ(sd50.modifiers[0].value->number, 2.5e3);
  EXPECT_EQ(sd50.modifiers[0].value_text, "2.5e3");
  EXPECT_EQ(sd50.modifiers[0].loc.ToString(), "test.yaml:102:33");
  EXPECT_EQ(sd50.modifiers[0].key_loc.ToString(), "test.yaml:102:30");
  EXPECT_EQ(sd50.modifiers[1].value->number, 0.5);
  EXPECT_EQ(sd50.modifiers[2].value->number, 40);
  EXPECT_EQ(sd50.modifiers[2].value_unit, "cm");
  const ComponentSpec& mass50 = spec.components[100];
  EXPECT_EQ(mass50.modifiers[2].key, "s");
  EXPECT_EQ(mass50.modifiers[2].start->number, 50);
  EXPECT_EQ(mass50.modifiers[2].fixed, true);
  // A plain end is held as text; its tree is made when asked.
  EXPECT_EQ(spec.connections[0].a, nullptr);
  EXPECT_EQ(spec.connections[0].EndA()->PathText(), "wall.flange");
  EXPECT_EQ(spec.connections[0].EndA()->path.size(), 2u);
  EXPECT_EQ(spec.connections[0].a_loc.ToString(), "test.yaml:125:6");
}

}  // namespace
}  // namespace momenta
