// The choice of a YAML reader (core/lang/yaml_document.h): a large file is read by libyaml or the
// subset reader as yaml-cpp reads it, inside and outside the subset, and its errors are yaml-cpp's
// at the same place; a model's errors name their line.

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "core/base/error.h"
#include "core/lang/model_spec.h"
#include "core/lang/yaml_document.h"
#include "core/lang/yaml_fast.h"
#include "core/lang/yaml_loader.h"
#include "tests/core/lang/yaml_dump.h"

namespace momenta {
namespace {

using testing::LargeModel;
using testing::Read;
using testing::ReadSubset;

TEST(YamlDocumentTest, LargeFileReadsTheSameEitherWay) {
  const std::string text = LargeModel();
  ASSERT_GE(text.size(), kLargeYamlBytes);
  EXPECT_EQ(Read(text, YamlReader::kAuto), Read(text, YamlReader::kYamlCpp));
  const ModelSpec spec = LoadModelString(text, "big.yaml");
  EXPECT_EQ(spec.components.size(), 6001u);
  EXPECT_EQ(spec.connections.size(), 6000u);
  EXPECT_EQ(spec.components.back().loc.line, 6003);
}

TEST(YamlDocumentTest, LargeFileErrorsAreYamlCppsAtTheSamePlace) {
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

TEST(YamlDocumentTest, LargeFileOutsideTheSubsetLoadsTheSame) {
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

TEST(YamlDocumentTest, LargeFileModelErrorsNameTheirLine) {
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

}  // namespace
}  // namespace momenta
