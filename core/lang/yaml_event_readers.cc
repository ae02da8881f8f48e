// The event-parser readers (core/lang/yaml_event_readers.h): yaml-cpp's and libyaml's events
// turned into the nodes of a YamlDoc.

#include "core/lang/yaml_event_readers.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/parser.h>
#include <yaml.h>

#include <sstream>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace momenta {

// ---- yaml-cpp's event parser -------------------------------------------------------------------

namespace {

/// A yaml-cpp mark as the tree keeps it (its offset in the text is not kept).
YamlMark TreeMark(const YAML::Mark& mark) { return {mark.line, mark.column}; }

/// Builds the first document from yaml-cpp's events and stops at the start of a second.
class TreeBuilder : public YAML::EventHandler {
 public:
  struct SecondDocument {};

  explicit TreeBuilder(ParsedYaml* out) : out_(out) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++out_->documents == 2) {
      out_->second_mark = TreeMark(mark);
      out_->second_offset = static_cast<size_t>(mark.pos);
      out_->stuck = mark.pos == first_.pos;
      throw SecondDocument{};
    }
    first_ = mark;
    doc_ = std::make_unique<YamlDoc>();
  }
  void OnDocumentEnd() override { out_->doc = std::move(doc_); }
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    Anchor(anchor, doc_->AddNull(TreeMark(mark)));
  }
  void OnAlias(const YAML::Mark&, YAML::anchor_t anchor) override {
    doc_->AddAlias(anchors_.at(anchor));
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string& value) override {
    Anchor(anchor, doc_->AddScalar(TreeMark(mark), tag, value));
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    Anchor(anchor, doc_->Open(YamlDoc::Kind::kSequence, TreeMark(mark), tag));
  }
  void OnSequenceEnd() override { doc_->Close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    Anchor(anchor, doc_->Open(YamlDoc::Kind::kMap, TreeMark(mark), tag));
  }
  void OnMapEnd() override { doc_->Close(); }

 private:
  void Anchor(YAML::anchor_t anchor, uint32_t id) {
    if (anchor == YAML::NullAnchor) return;
    if (anchors_.size() <= anchor) anchors_.resize(anchor + 1);
    anchors_[anchor] = id;
  }

  ParsedYaml* out_;
  std::unique_ptr<YamlDoc> doc_;
  std::vector<uint32_t> anchors_;
  YAML::Mark first_;
};

}  // namespace

ParsedYaml ParseWithYamlCpp(const std::string& text) {
  ParsedYaml out;
  std::istringstream stream(text);
  YAML::Parser parser(stream);
  TreeBuilder builder(&out);
  try {
    while (parser.HandleNextDocument(builder)) {
    }
  } catch (const TreeBuilder::SecondDocument&) {
  }
  return out;
}

// ---- libyaml's event parser --------------------------------------------------------------------

namespace {

/// Deeper nesting than this is left to yaml-cpp, whose depth limit gives the error.
constexpr int kLibyamlMaxDepth = 100;

/// A libyaml mark as the tree keeps it.
YamlMark TreeMark(const yaml_mark_t& mark) {
  return {static_cast<int>(mark.line), static_cast<int>(mark.column)};
}

/// yaml-cpp's tag for a node libyaml reports: the explicit tag, or "!" for an untagged quoted or
/// block scalar, "?" for an untagged plain one.
uint32_t TagOf(YamlDoc* doc, const yaml_char_t* tag, bool plain) {
  if (tag) return doc->TagIndex(reinterpret_cast<const char*>(tag));
  return plain ? YamlDoc::kUntagged : YamlDoc::kNonSpecific;
}

bool IsNullText(std::string_view s) {
  return s.empty() || s == "~" || s == "null" || s == "Null" || s == "NULL";
}

struct LibyamlParser {
  yaml_parser_t parser;
  LibyamlParser() { yaml_parser_initialize(&parser); }
  ~LibyamlParser() { yaml_parser_delete(&parser); }
};

struct LibyamlEvent {
  yaml_event_t event;
  ~LibyamlEvent() { yaml_event_delete(&event); }
};

}  // namespace

std::unique_ptr<YamlDoc> ParseWithLibyaml(const std::string& text) {
  LibyamlParser p;
  yaml_parser_set_input_string(&p.parser, reinterpret_cast<const unsigned char*>(text.data()),
                               text.size());
  auto doc = std::make_unique<YamlDoc>();
  doc->Reserve(text.size());
  std::unordered_map<std::string, uint32_t> anchors;
  auto anchor = [&](const yaml_char_t* name, uint32_t id) {
    if (name) anchors[reinterpret_cast<const char*>(name)] = id;
  };
  int documents = 0, depth = 0;
  for (;;) {
    LibyamlEvent e;
    if (!yaml_parser_parse(&p.parser, &e.event)) return nullptr;
    const yaml_event_t& ev = e.event;
    switch (ev.type) {
      case YAML_STREAM_START_EVENT:
      case YAML_DOCUMENT_END_EVENT:
      case YAML_NO_EVENT:
        break;
      case YAML_STREAM_END_EVENT:
        return documents == 1 ? std::move(doc) : nullptr;
      case YAML_DOCUMENT_START_EVENT:
        if (++documents > 1) return nullptr;
        break;
      case YAML_SCALAR_EVENT: {
        const auto& s = ev.data.scalar;
        const std::string_view value(reinterpret_cast<const char*>(s.value), s.length);
        const bool plain = s.style == YAML_PLAIN_SCALAR_STYLE;
        // yaml-cpp places an empty value (`key:` and nothing) where the next token starts, libyaml
        // in some places right after the ':': such a file is left to yaml-cpp.
        if (plain && s.length == 0) return nullptr;
        if (plain && !s.tag && IsNullText(value)) {
          anchor(s.anchor, doc->AddNull(TreeMark(ev.start_mark)));
        } else {
          anchor(s.anchor,
                 doc->AddScalar(TreeMark(ev.start_mark), TagOf(doc.get(), s.tag, plain), value));
        }
        break;
      }
      case YAML_SEQUENCE_START_EVENT:
        if (++depth > kLibyamlMaxDepth) return nullptr;
        anchor(ev.data.sequence_start.anchor,
               doc->Open(YamlDoc::Kind::kSequence, TreeMark(ev.start_mark),
                         TagOf(doc.get(), ev.data.sequence_start.tag, true)));
        break;
      case YAML_MAPPING_START_EVENT:
        if (++depth > kLibyamlMaxDepth) return nullptr;
        anchor(ev.data.mapping_start.anchor,
               doc->Open(YamlDoc::Kind::kMap, TreeMark(ev.start_mark),
                         TagOf(doc.get(), ev.data.mapping_start.tag, true)));
        break;
      case YAML_SEQUENCE_END_EVENT:
      case YAML_MAPPING_END_EVENT:
        --depth;
        doc->Close();
        break;
      case YAML_ALIAS_EVENT: {
        auto it = anchors.find(reinterpret_cast<const char*>(ev.data.alias.anchor));
        if (it == anchors.end()) return nullptr;
        doc->AddAlias(it->second);
        break;
      }
    }
  }
}

}  // namespace momenta
