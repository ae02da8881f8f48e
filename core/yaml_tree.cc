#include "core/yaml_tree.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/parser.h>
#include <yaml.h>

#include <atomic>
#include <sstream>
#include <unordered_map>

namespace momenta {

// ---- YamlNode: yaml-cpp's answers, on the flat document ------------------------------------

void YamlNode::CheckValid() const {
  if (!IsDefined()) throw YAML::InvalidNode(missing_key_ ? *missing_key_ : std::string());
}

bool YamlNode::IsNull() const {
  CheckValid();
  return doc_->item(id_).kind == YamlDoc::Kind::kNull;
}
bool YamlNode::IsScalar() const {
  CheckValid();
  return doc_->item(id_).kind == YamlDoc::Kind::kScalar;
}
bool YamlNode::IsSequence() const {
  CheckValid();
  return doc_->item(id_).kind == YamlDoc::Kind::kSequence;
}
bool YamlNode::IsMap() const {
  CheckValid();
  return doc_->item(id_).kind == YamlDoc::Kind::kMap;
}

const std::string& YamlNode::Scalar() const {
  CheckValid();
  return IsScalar() ? doc_->scalar(id_) : YamlDoc::EmptyString();
}

const std::string& YamlNode::Tag() const {
  CheckValid();
  return doc_->tag(id_);
}

YAML::Mark YamlNode::Mark() const {
  CheckValid();
  return doc_->item(id_).mark;
}

size_t YamlNode::size() const {
  CheckValid();
  const YamlDoc::Item& it = doc_->item(id_);
  if (it.kind == YamlDoc::Kind::kSequence) return it.count;
  if (it.kind == YamlDoc::Kind::kMap) return it.count / 2;
  return 0;
}

YamlNode YamlNode::operator[](const std::string& key) const {
  CheckValid();
  const YamlDoc::Item& it = doc_->item(id_);
  if (it.kind == YamlDoc::Kind::kScalar) throw YAML::BadSubscript(it.mark, key);
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
  return Scalar();
}

YamlNode::Iterator YamlNode::begin() const { return Iterator(*this, 0); }

YamlNode::Iterator YamlNode::end() const {
  // Like yaml-cpp, an invalid node iterates as empty.
  return Iterator(*this, IsDefined() ? size() : 0);
}

YamlNode::Entry YamlNode::Iterator::operator*() const {
  Entry e;
  const YamlDoc* doc = owner_.doc_;
  if (doc->item(owner_.id_).kind == YamlDoc::Kind::kMap) {
    e.first = YamlNode(doc, doc->child(owner_.id_, 2 * k_));
    e.second = YamlNode(doc, doc->child(owner_.id_, 2 * k_ + 1));
  } else {
    static_cast<YamlNode&>(e) = YamlNode(doc, doc->child(owner_.id_, k_));
  }
  return e;
}

// ---- YamlDoc: building ----------------------------------------------------------------------

YamlDoc::YamlDoc() : tags_{"?", "!"} {}

const std::string& YamlDoc::EmptyString() {
  static const std::string empty;
  return empty;
}

uint32_t YamlDoc::TagIndex(const std::string& tag) {
  if (tag.empty() || tag == "?") return 0;
  if (tag == "!") return 1;
  for (uint32_t k = 2; k < tags_.size(); ++k) {
    if (tags_[k] == tag) return k;
  }
  tags_.push_back(tag);
  return static_cast<uint32_t>(tags_.size() - 1);
}

void YamlDoc::Attach(uint32_t id) {
  if (!open_.empty()) pending_.push_back(id);
}

uint32_t YamlDoc::AddScalar(const YAML::Mark& mark, const std::string& tag, std::string value) {
  Item it;
  it.kind = Kind::kScalar;
  it.tag = TagIndex(tag);
  it.first = static_cast<uint32_t>(scalars_.size());
  it.mark = mark;
  scalars_.push_back(std::move(value));
  const auto id = static_cast<uint32_t>(items_.size());
  items_.push_back(it);
  Attach(id);
  return id;
}

uint32_t YamlDoc::AddNull(const YAML::Mark& mark) {
  Item it;
  it.mark = mark;
  const auto id = static_cast<uint32_t>(items_.size());
  items_.push_back(it);
  Attach(id);
  return id;
}

uint32_t YamlDoc::Open(Kind kind, const YAML::Mark& mark, const std::string& tag) {
  Item it;
  it.kind = kind;
  it.tag = TagIndex(tag);
  it.mark = mark;
  const auto id = static_cast<uint32_t>(items_.size());
  items_.push_back(it);
  Attach(id);
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
std::string TagOf(const yaml_char_t* tag, bool plain) {
  if (tag) return reinterpret_cast<const char*>(tag);
  return plain ? "?" : "!";
}

bool IsNullText(const std::string& s) {
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
        std::string value(reinterpret_cast<const char*>(s.value), s.length);
        const bool plain = s.style == YAML_PLAIN_SCALAR_STYLE;
        // yaml-cpp places an empty value (`key:` and nothing) where the next token starts, libyaml
        // in some places right after the ':': such a file is left to yaml-cpp.
        if (plain && s.length == 0) return nullptr;
        if (plain && !s.tag && IsNullText(value)) {
          anchor(s.anchor, doc->AddNull(ToMark(ev.start_mark)));
        } else {
          anchor(s.anchor, doc->AddScalar(ToMark(ev.start_mark), TagOf(s.tag, plain), std::move(value)));
        }
        break;
      }
      case YAML_SEQUENCE_START_EVENT:
        if (++depth > kLibyamlMaxDepth) return nullptr;
        anchor(ev.data.sequence_start.anchor,
               doc->Open(YamlDoc::Kind::kSequence, ToMark(ev.start_mark), TagOf(ev.data.sequence_start.tag, true)));
        break;
      case YAML_MAPPING_START_EVENT:
        if (++depth > kLibyamlMaxDepth) return nullptr;
        anchor(ev.data.mapping_start.anchor,
               doc->Open(YamlDoc::Kind::kMap, ToMark(ev.start_mark), TagOf(ev.data.mapping_start.tag, true)));
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
