// The choice of a YAML reader (core/lang/yaml_document.h).

#include "core/lang/yaml_document.h"

#include <atomic>
#include <memory>

#include "core/lang/yaml_event_readers.h"
#include "core/lang/yaml_fast.h"

namespace momenta {

namespace {

std::atomic<YamlReader> g_default_reader{YamlReader::kAuto};

bool IsAscii(const std::string& text) {
  unsigned char any = 0;
  for (unsigned char c : text) any |= c;
  return (any & 0x80) == 0;
}

/// A document a reader accepted whole: one document, nothing after it.
ParsedYaml OneDocument(std::unique_ptr<YamlDoc> doc) {
  ParsedYaml out;
  out.doc = std::move(doc);
  out.documents = 1;
  return out;
}

}  // namespace

void SetDefaultYamlReader(YamlReader reader) { g_default_reader = reader; }

ParsedYaml ParseYamlDocument(const std::string& text, YamlReader reader) {
  if (reader == YamlReader::kAuto) reader = g_default_reader;
  if (reader == YamlReader::kAuto || reader == YamlReader::kSubset) {
    if (std::unique_ptr<YamlDoc> doc = ParseYamlSubset(text)) return OneDocument(std::move(doc));
  }
  // libyaml counts columns in characters and yaml-cpp in bytes: they agree on ASCII text only.
  const bool libyaml = reader == YamlReader::kLibyaml ||
                       (reader == YamlReader::kAuto && text.size() >= kLargeYamlBytes);
  if (libyaml && IsAscii(text)) {
    if (std::unique_ptr<YamlDoc> doc = ParseWithLibyaml(text)) return OneDocument(std::move(doc));
  }
  return ParseWithYamlCpp(text);
}

}  // namespace momenta
