// The YAML document tree (core/lang/yaml_tree.h): yaml-cpp's answers and exceptions on the flat
// document, and the building of it from a reader's events.

#include "core/lang/yaml_tree.h"

#include <yaml-cpp/exceptions.h>

namespace momenta {

namespace {

/// yaml-cpp's mark for a node, for the exceptions it would throw there (its position in the text
/// is not kept: yaml-cpp's messages give the line and column only).
YAML::Mark YamlCppMark(const YamlMark& mark) {
  YAML::Mark out;
  out.line = mark.line;
  out.column = mark.column;
  return out;
}

}  // namespace

// ---- YamlNode: yaml-cpp's answers, on the flat document ------------------------------------

void YamlNode::ThrowInvalid() const {
  throw YAML::InvalidNode(doc_ && missing_key_ != kNoKey ? doc_->missing_keys_[missing_key_]
                                                         : std::string());
}

YamlNode YamlNode::operator[](std::string_view key) const {
  CheckValid();
  const YamlDoc::Item& it = doc_->item(id_);
  if (it.kind == YamlDoc::Kind::kScalar) throw YAML::BadSubscript(YamlCppMark(it.mark), std::string(key));
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
  if (it.kind == YamlDoc::Kind::kScalar) throw YAML::BadSubscript(YamlCppMark(it.mark), k);
  if (it.kind == YamlDoc::Kind::kSequence && k < it.count) return YamlNode(doc_, doc_->child(id_, k));
  // A mapping's key "0", "1", … as yaml-cpp compares keys by their text.
  if (it.kind == YamlDoc::Kind::kMap) return (*this)[std::to_string(k)];
  return doc_->Zombie(std::to_string(k));
}

std::string_view YamlNode::AsText() const {
  if (IsNull()) return "null";
  if (!IsScalar()) throw YAML::TypedBadConversion<std::string>(YamlCppMark(Mark()));
  return Scalar();
}

template <>
std::string YamlNode::as<std::string>() const {
  return std::string(AsText());
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

uint32_t YamlDoc::AddScalar(const YamlMark& mark, const std::string& tag,
                            std::string_view value) {
  return AddScalar(mark, TagIndex(tag), value);
}

uint32_t YamlDoc::Open(Kind kind, const YamlMark& mark, const std::string& tag) {
  return Open(kind, mark, TagIndex(tag));
}

uint32_t YamlDoc::Open(Kind kind, const YamlMark& mark, uint32_t tag) {
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
  // This runs once per mapping, a large part of reading the written-out chain: small mappings
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

}  // namespace momenta
