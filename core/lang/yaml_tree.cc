#include "core/lang/yaml_tree.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/parser.h>
#include <yaml.h>

#include <atomic>
#include <sstream>
#include <unordered_map>

#include "core/lang/yaml_fast.h"

namespace momenta {

// ---- YamlNode: yaml-cpp's answers, on the flat document ------------------------------------

void YamlNode::ThrowInvalid() const {
  throw YAML::InvalidNode(doc_ && missing_key_ != kNoKey ? doc_->missing_keys_[missing_key_]
                                                         : std::string());
}

YamlNode YamlNode::operator[](std::string_view key) const {
  CheckValid();
  const YamlDoc::Item& it = doc_->item(id_);
  if (it.kind == YamlDoc::Kind::kScalar) throw YAML::BadSubscript(it.mark, std::string(key));
  if (it.kind == YamlDoc::Kind::kMap) {
    for (uint32_t k = 0; k < it.count; k += 2) {
      const uint32_t key_id = doc_->child(id_, k);
      if (doc_->item(key_id).kind == YamlDoc::Kind::kScalar && doc_->scalar(key_id) == key) {
        return YamlNode(doc_, doc_->child(id_, k + 1));
      }
    }
  }
  return doc_->Zombie(key);
}

YamlNode YamlNode::operator[](size_t k) const {
  CheckValid();
  const YamlDoc::Item& it = doc_->item(id_);
  if (it.kind == YamlDoc::Kind::kScalar) throw YAML::BadSubscript(it.mark, k);
  if (it.kind == YamlDoc::Kind::kSequence && k < it.count) return YamlNode(doc_, doc_->child(id_, k));
  // A mapping's key "0", "1", … as yaml-cpp compares keys by their text.
  if (it.kind == YamlDoc::Kind::kMap) return (*this)[std::to_string(k)];
  return doc_->Zombie(std::to_string(k));
}

template <>
std::string YamlNode::as<std::string>() const {
  if (IsNull()) return "null";
  if (!IsScalar()) throw YAML::TypedBadConversion<std::string>(Mark());
  return std::string(Scalar());
}

// ---- YamlDoc: building ----------------------------------------------------------------------

YamlDoc::YamlDoc() : tags_{"?", "!"} {}

void YamlDoc::Reserve(size_t text_bytes) {
  // Model files hold a node per 6.7 bytes (the written-out chain, flow mappings of short values)
  // to 10 (library files); a denser text only makes the arrays grow. Scalars are never longer
  // than their text.
  items_.reserve(text_bytes / 6 + 1);
  children_.reserve(text_bytes / 6 + 1);
  texts_.reserve(text_bytes);
}

YamlNode YamlDoc::Zombie(std::string_view key) const {
  // The keys missed last are the likeliest to be missed again.
  for (size_t k = missing_keys_.size(); k-- > 0;) {
    if (missing_keys_[k] == key) return YamlNode(this, YamlNode::kZombie, static_cast<uint32_t>(k));
  }
  missing_keys_.emplace_back(key);
  return YamlNode(this, YamlNode::kZombie, static_cast<uint32_t>(missing_keys_.size() - 1));
}

uint32_t YamlDoc::TagIndex(std::string_view tag) {
  if (tag.empty() || tag == "?") return kUntagged;
  if (tag == "!") return kNonSpecific;
  for (uint32_t k = 2; k < tags_.size(); ++k) {
    if (tags_[k] == tag) return k;
  }
  tags_.emplace_back(tag);
  return static_cast<uint32_t>(tags_.size() - 1);
}

uint32_t YamlDoc::AddScalar(const YAML::Mark& mark, const std::string& tag,
                            std::string_view value) {
  return AddScalar(mark, TagIndex(tag), value);
}

uint32_t YamlDoc::Open(Kind kind, const YAML::Mark& mark, const std::string& tag) {
  return Open(kind, mark, TagIndex(tag));
}

uint32_t YamlDoc::Open(Kind kind, const YAML::Mark& mark, uint32_t tag) {
  Item it;
  it.kind = kind;
  it.tag = tag;
  it.mark = mark;
  const uint32_t id = Add(it);
  open_.emplace_back(id, pending_.size());
  return id;
}

void YamlDoc::Close() {
  const auto [id, start] = open_.back();
  open_.pop_back();
  items_[id].first = static_cast<uint32_t>(children_.size());
  items_[id].count = static_cast<uint32_t>(pending_.size() - start);
  children_.insert(children_.end(), pending_.begin() + static_cast<std::ptrdiff_t>(start), pending_.end());
  pending_.resize(start);
  if (items_[id].kind == Kind::kMap && !repeated_key_) repeated_key_ = RepeatsAKey(id);
}

bool YamlDoc::RepeatsAKey(uint32_t map) const {
  const Item& it = items_[map];
  auto key = [&](uint32_t k, std::string_view* text) {
    const uint32_t id = children_[it.first + 2 * k];
    if (items_[id].kind != Kind::kScalar) return false;
    *text = scalar(id);
    return true;
  };
  const uint32_t pairs = it.count / 2;
  std::string_view a, b;
  // This runs once per mapping and cost a third of reading the written-out chain: small mappings
  // (a component's few keys) compare their scalar keys pairwise, gathered first into an array
  // left uninitialised; large ones (a model's components) use an open-addressed table of key
  // numbers (a node-based set cost a heap block per key).
  constexpr uint32_t kPairwise = 16;
  if (pairs <= kPairwise) {
    const char* text[kPairwise];
    uint32_t size[kPairwise];
    uint32_t n = 0;
    for (uint32_t i = 0; i < pairs; ++i) {
      if (!key(i, &a)) continue;
      for (uint32_t j = 0; j < n; ++j) {
        if (size[j] == a.size() && std::string_view(text[j], size[j]) == a) return true;
      }
      text[n] = a.data();
      size[n++] = static_cast<uint32_t>(a.size());
    }
    return false;
  }
  size_t capacity = 1;
  while (capacity < 2 * size_t{pairs}) capacity <<= 1;
  constexpr uint32_t kEmpty = ~0u;
  std::vector<uint32_t> slots(capacity, kEmpty);
  for (uint32_t i = 0; i < pairs; ++i) {
    if (!key(i, &a)) continue;
    size_t h = std::hash<std::string_view>{}(a) & (capacity - 1);
    for (; slots[h] != kEmpty; h = (h + 1) & (capacity - 1)) {
      if (key(slots[h], &b) && a == b) return true;
    }
    slots[h] = i;
  }
  return false;
}

// ---- yaml-cpp's event parser -------------------------------------------------------------------

namespace {

std::atomic<YamlReader> g_default_reader{YamlReader::kAuto};

/// Builds the first document from yaml-cpp's events and stops at the start of a second.
class TreeBuilder : public YAML::EventHandler {
 public:
  struct SecondDocument {};

  explicit TreeBuilder(ParsedYaml* out) : out_(out) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++out_->documents == 2) {
      out_->second_mark = mark;
      out_->stuck = mark.pos == first_.pos;
      throw SecondDocument{};
    }
    first_ = mark;
    doc_ = std::make_unique<YamlDoc>();
  }
  void OnDocumentEnd() override { out_->doc = std::move(doc_); }
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { Anchor(anchor, doc_->AddNull(mark)); }
  void OnAlias(const YAML::Mark&, YAML::anchor_t anchor) override { doc_->AddAlias(anchors_.at(anchor)); }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string& value) override {
    Anchor(anchor, doc_->AddScalar(mark, tag, value));
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    Anchor(anchor, doc_->Open(YamlDoc::Kind::kSequence, mark, tag));
  }
  void OnSequenceEnd() override { doc_->Close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    Anchor(anchor, doc_->Open(YamlDoc::Kind::kMap, mark, tag));
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

/// Deeper nesting than this is left to yaml-cpp, whose depth limit gives the error.
constexpr int kLibyamlMaxDepth = 100;

YAML::Mark ToMark(const yaml_mark_t& m) {
  YAML::Mark mark;
  mark.pos = static_cast<int>(m.index);
  mark.line = static_cast<int>(m.line);
  mark.column = static_cast<int>(m.column);
  return mark;
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

/// The document read with libyaml, or no document when libyaml reports an error, the text holds
/// other than exactly one document, an alias names an unknown anchor, the nesting is deep, or a
/// value is empty:
/// yaml-cpp reads those again and says what is wrong in its words.
std::unique_ptr<YamlDoc> ParseWithLibyaml(const std::string& text) {
  LibyamlParser p;
  yaml_parser_set_input_string(&p.parser, reinterpret_cast<const unsigned char*>(text.data()), text.size());
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
          anchor(s.anchor, doc->AddNull(ToMark(ev.start_mark)));
        } else {
          anchor(s.anchor,
                 doc->AddScalar(ToMark(ev.start_mark), TagOf(doc.get(), s.tag, plain), value));
        }
        break;
      }
      case YAML_SEQUENCE_START_EVENT:
        if (++depth > kLibyamlMaxDepth) return nullptr;
        anchor(ev.data.sequence_start.anchor,
               doc->Open(YamlDoc::Kind::kSequence, ToMark(ev.start_mark),
                         TagOf(doc.get(), ev.data.sequence_start.tag, true)));
        break;
      case YAML_MAPPING_START_EVENT:
        if (++depth > kLibyamlMaxDepth) return nullptr;
        anchor(ev.data.mapping_start.anchor,
               doc->Open(YamlDoc::Kind::kMap, ToMark(ev.start_mark),
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

bool IsAscii(const std::string& text) {
  unsigned char any = 0;
  for (unsigned char c : text) any |= c;
  return (any & 0x80) == 0;
}

}  // namespace

void SetDefaultYamlReader(YamlReader reader) { g_default_reader = reader; }

ParsedYaml ParseYamlDocument(const std::string& text, YamlReader reader) {
  if (reader == YamlReader::kAuto) reader = g_default_reader;
  if (reader == YamlReader::kAuto || reader == YamlReader::kSubset) {
    if (std::unique_ptr<YamlDoc> doc = ParseYamlSubset(text)) {
      ParsedYaml out;
      out.doc = std::move(doc);
      out.documents = 1;
      return out;
    }
  }
  // libyaml counts columns in characters and yaml-cpp in bytes: they agree on ASCII text only.
  const bool libyaml = reader == YamlReader::kLibyaml ||
                       (reader == YamlReader::kAuto && text.size() >= kLargeYamlBytes);
  if (libyaml && IsAscii(text)) {
    if (std::unique_ptr<YamlDoc> doc = ParseWithLibyaml(text)) {
      ParsedYaml out;
      out.doc = std::move(doc);
      out.documents = 1;
      return out;
    }
  }
  return ParseWithYamlCpp(text);
}

}  // namespace momenta
