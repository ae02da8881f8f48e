#pragma once
/// The two readers of YAML that are event parsers, each filling a YamlDoc (core/lang/yaml_tree.h)
/// from its events: yaml-cpp's, which defines the format and gives every message, and libyaml's,
/// several times faster (bench/RESULTS.md), for large files the subset reader
/// (core/lang/yaml_fast.h) refuses. Which one reads a text is core/lang/yaml_document.h's choice;
/// yaml-cpp's and libyaml's headers stay in yaml_event_readers.cc.

#include <memory>
#include <string>

#include "core/lang/yaml_tree.h"

namespace momenta {

/// The first document of `text` read with yaml-cpp's event parser, stopping at the start of a
/// second. yaml-cpp's exceptions (YAML::ParserException, YAML::DeepRecursion) pass through.
ParsedYaml ParseWithYamlCpp(const std::string& text);

/// The document of `text` read with libyaml's event parser, or null when libyaml reports an
/// error, the text holds other than exactly one document, an alias names an unknown anchor, the
/// nesting is deeper than 100 levels, or a plain value is empty: yaml-cpp reads those again and
/// says what is wrong in its words. Columns are libyaml's (characters): equal to yaml-cpp's
/// (bytes) on ASCII text only.
std::unique_ptr<YamlDoc> ParseWithLibyaml(const std::string& text);

}  // namespace momenta
