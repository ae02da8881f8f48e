// The YAML document tree (core/lang/yaml_tree.h): its nodes answer as yaml-cpp's YAML::Node does,
// with the same exceptions. That the readers fill it alike is tested beside each reader
// (yaml_fast_test, yaml_event_readers_test, yaml_document_test).

#include <gtest/gtest.h>
#include <yaml-cpp/exceptions.h>

#include <string>

#include "core/lang/yaml_document.h"
#include "core/lang/yaml_tree.h"

namespace momenta {
namespace {

TEST(YamlTreeTest, NodeAnswersAsYamlCppNodes) {
  ParsedYaml p = ParseYamlDocument("a: {b: 1}\nc: [x, y]\nd:\n", YamlReader::kYamlCpp);
  const YamlNode root = p.doc->root();
  EXPECT_FALSE(root["missing"]);
  EXPECT_THROW(root["missing"].IsMap(), YAML::InvalidNode);
  EXPECT_THROW(root["a"]["b"]["z"], YAML::BadSubscript);
  EXPECT_EQ(root["c"][1].Scalar(), "y");
  // Marks are 0-based, as yaml-cpp's: "y" is on the second line, eighth column.
  EXPECT_EQ(root["c"][1].Mark().line, 1);
  EXPECT_EQ(root["c"][1].Mark().column, 7);
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
