#pragma once
/// Which reader reads a YAML text into a YamlDoc (core/lang/yaml_tree.h): the subset reader
/// (core/lang/yaml_fast.h) first, which reads model files several times faster than the others;
/// what it refuses, libyaml's event parser for a large ASCII text and yaml-cpp's otherwise
/// (core/lang/yaml_event_readers.h). The choice sits above the readers, so that each of them
/// depends on the tree only.

#include <cstddef>
#include <string>

#include "core/lang/yaml_tree.h"

namespace momenta {

/// Which parser reads the text (ParseYamlDocument).
enum class YamlReader {
  /// The subset reader (core/lang/yaml_fast.h); what it refuses, libyaml for large ASCII texts
  /// (kLargeYamlBytes and up), yaml-cpp otherwise.
  kAuto,
  kYamlCpp,  ///< yaml-cpp's event parser, always
  kLibyaml,  ///< libyaml first, whatever the size (yaml-cpp again when libyaml finds an error)
  kSubset,   ///< the subset reader first, yaml-cpp for what it refuses
};

/// From this size on, kAuto reads with libyaml what the subset reader refuses.
constexpr size_t kLargeYamlBytes = size_t{256} << 10;

/// The first document of `text` as a YamlDoc, read by `reader` (ParsedYaml says how many
/// documents were seen). yaml-cpp's exceptions (YAML::ParserException, YAML::DeepRecursion) pass
/// through.
ParsedYaml ParseYamlDocument(const std::string& text, YamlReader reader = YamlReader::kAuto);

/// The reader used by ParseYamlDocument's kAuto (for tests comparing the two parsers).
void SetDefaultYamlReader(YamlReader reader);

}  // namespace momenta
