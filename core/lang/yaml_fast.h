#pragma once
/// A reader written for the part of YAML that model files use, filling the same YamlDoc as the
/// event parsers (core/lang/yaml_event_readers.h) with the same nodes, tags and marks: block
/// mappings and sequences by indentation (also a sequence at its key's indentation and
/// `- key: value` items), flow sequences and mappings (over several lines when broken between
/// entries), plain scalars and single- and double-quoted scalars on one line (the escapes of ASCII
/// characters), literal and folded block scalars (`|`, `>`, `|-`, `>-`) whose lines are equally
/// indented, comments. It reads the written-out chain several times faster than libyaml
/// (bench/RESULTS.md): no tokens, no events, one pass.
///
/// It refuses everything else (anchors, aliases, tags, `?` keys, document markers and directives,
/// a plain or quoted scalar continued on the next line, an empty value other than `key:` followed
/// by the next key, tabs, carriage returns, control bytes, a text that starts with a non-ASCII
/// byte (a byte-order mark, UTF-16), nesting deeper than 100 levels) and every error: the other
/// readers then read the text, so that what is outside the subset, and every message, stays
/// yaml-cpp's.

#include <memory>
#include <string>

#include "core/lang/yaml_tree.h"

namespace momenta {

/// The document of `text`, or null when the text goes outside the subset or is not valid YAML.
/// An accepted text holds exactly one document, and the YamlDoc equals the one yaml-cpp's event
/// parser builds from it (tests/core/lang/yaml_tree_test.cc compares them).
std::unique_ptr<YamlDoc> ParseYamlSubset(const std::string& text);

}  // namespace momenta
