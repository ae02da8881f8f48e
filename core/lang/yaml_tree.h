#pragma once
/// A read-only YAML document as the model loader walks it: one flat array of nodes built from a
/// parser's events, with the part of yaml-cpp's YAML::Node interface the loader uses (and the same
/// answers and exceptions). yaml-cpp's own node tree costs a heap node, a shared pointer and a
/// memory holder per value; for a model of 100 000 written-out components that tree took longer
/// than everything else the loader does. Three readers fill it: yaml-cpp's event parser, which
/// defines the format, and libyaml's, faster, for large ASCII files (core/lang/yaml_event_readers.h);
/// and a reader of the subset of YAML that model files use, faster still, which refuses everything
/// else (core/lang/yaml_fast.h). Whatever the faster readers refuse or cannot read is read again
/// with yaml-cpp, so errors are yaml-cpp's (core/lang/yaml_document.h picks the reader; the
/// figures are in bench/RESULTS.md). The tree depends on no reader: yaml-cpp's exceptions are
/// thrown from yaml_tree.cc, and its headers stay out of this one.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace momenta {

class YamlDoc;

/// Where a node starts in its text, 0-based as yaml-cpp's marks (messages add 1).
struct YamlMark {
  int line = 0;
  int column = 0;
};

/// A node of a YamlDoc, or a "zombie": the result of looking up a key that is not there, which
/// converts to false (like YAML::Node's).
class YamlNode {
 public:
  YamlNode() = default;
  YamlNode(const YamlDoc* doc, uint32_t id) : doc_(doc), id_(id) {}

  explicit operator bool() const { return IsDefined(); }
  bool IsDefined() const { return doc_ != nullptr && id_ != kZombie; }
  bool IsNull() const;
  bool IsScalar() const;
  bool IsSequence() const;
  bool IsMap() const;
  /// The text of a scalar; "" for anything else. A view into the document: valid as long as it.
  std::string_view Scalar() const;
  /// "!" for a quoted scalar or one tagged '!', the explicit tag otherwise, "?" when untagged.
  const std::string& Tag() const;
  YamlMark Mark() const;
  /// Elements of a sequence, pairs of a mapping, 0 otherwise.
  size_t size() const;
  /// The value of `key` in a mapping (the first pair with that scalar key); a zombie when there is
  /// none, or when this is null or a sequence. Throws YAML::BadSubscript on a scalar.
  YamlNode operator[](std::string_view key) const;
  YamlNode operator[](const std::string& key) const { return (*this)[std::string_view(key)]; }
  YamlNode operator[](const char* key) const { return (*this)[std::string_view(key)]; }
  /// Element k of a sequence; a zombie past its end or on anything else but a scalar.
  YamlNode operator[](size_t k) const;
  YamlNode operator[](int k) const { return (*this)[static_cast<size_t>(k)]; }
  /// The scalar's text, "null" for a null; throws YAML::TypedBadConversion otherwise.
  template <typename T>
  T as() const;
  /// What as<std::string>() gives, without a copy: a view into the document for a scalar,
  /// "null" for a null; throws YAML::TypedBadConversion for a sequence or mapping.
  std::string_view AsText() const;

  /// What iterating yields: for a sequence the element itself, for a mapping a pair (first,
  /// second), as YAML::Node's iterators do.
  struct Entry;
  class Iterator;
  Iterator begin() const;
  Iterator end() const;

  uint32_t id() const { return id_; }

 private:
  friend class YamlDoc;
  static constexpr uint32_t kZombie = ~0u;
  YamlNode(const YamlDoc* doc, uint32_t id, uint32_t missing_key)
      : doc_(doc), id_(id), missing_key_(missing_key) {}
  void CheckValid() const {
    if (!IsDefined()) ThrowInvalid();
  }
  [[noreturn]] void ThrowInvalid() const;

  const YamlDoc* doc_ = nullptr;
  uint32_t id_ = kZombie;
  /// A zombie's key, for its InvalidNode message: an index into its document's missing keys
  /// (kNoKey for none). An index, not a string: looking up an absent key stays free of heap blocks.
  static constexpr uint32_t kNoKey = ~0u;
  uint32_t missing_key_ = kNoKey;
};

struct YamlNode::Entry : YamlNode {
  YamlNode first, second;
};

class YamlNode::Iterator {
 public:
  Iterator(const YamlNode& owner, size_t k) : owner_(owner), k_(k) {}
  bool operator==(const Iterator& o) const { return k_ == o.k_; }
  bool operator!=(const Iterator& o) const { return k_ != o.k_; }
  Iterator& operator++() {
    ++k_;
    return *this;
  }
  Entry operator*() const;
  struct Arrow {
    Entry e;
    const Entry* operator->() const { return &e; }
  };
  Arrow operator->() const { return {**this}; }

 private:
  YamlNode owner_;
  size_t k_;
};

/// The nodes of one document. Node 0 is the root. The texts of all scalars are kept end to end in
/// one buffer (a string per scalar cost a heap block each on a 100 000-component file).
class YamlDoc {
 public:
  enum class Kind : uint8_t { kNull, kScalar, kSequence, kMap };
  struct Item {
    Kind kind = Kind::kNull;
    uint32_t tag = 0;     ///< index into tags_: 0 "?", 1 "!", others explicit tags
    uint32_t first = 0;   ///< scalar: offset into texts_; collection: first index into children_
    uint32_t count = 0;   ///< scalar: length of its text; collection: children (a mapping's are
                          ///< key, value, key, value, ...)
    YamlMark mark;
  };

  YamlDoc();
  /// Room for a document parsed from `text_bytes` bytes of YAML, so that the arrays do not move
  /// while they grow (pages not written to are not used).
  void Reserve(size_t text_bytes);
  YamlNode root() const { return YamlNode(this, 0); }
  bool empty() const { return items_.empty(); }
  size_t num_nodes() const { return items_.size(); }
  /// Whether some mapping has a scalar key twice (found while building, so that a document
  /// without one is not walked again to look for it).
  bool has_repeated_key() const { return repeated_key_; }
  const Item& item(uint32_t id) const { return items_[id]; }
  std::string_view scalar(uint32_t id) const {
    return std::string_view(texts_.data() + items_[id].first, items_[id].count);
  }
  const std::string& tag(uint32_t id) const { return tags_[items_[id].tag]; }
  uint32_t child(uint32_t id, size_t k) const { return children_[items_[id].first + k]; }
  static const std::string& EmptyString();

  /// Building, in the order of a parser's events. A collection's children are gathered while it
  /// is open and stored together when it closes.
  uint32_t AddScalar(const YamlMark& mark, const std::string& tag, std::string_view value);
  /// The same with the tag as an index (kUntagged, kNonSpecific or a TagIndex).
  uint32_t AddScalar(const YamlMark& mark, uint32_t tag, std::string_view value) {
    Item it;
    it.kind = Kind::kScalar;
    it.tag = tag;
    it.first = static_cast<uint32_t>(texts_.size());
    it.count = static_cast<uint32_t>(value.size());
    it.mark = mark;
    texts_.append(value);
    return Add(it);
  }
  uint32_t AddNull(const YamlMark& mark) {
    Item it;
    it.mark = mark;
    return Add(it);
  }
  uint32_t Open(Kind kind, const YamlMark& mark, const std::string& tag);
  uint32_t Open(Kind kind, const YamlMark& mark, uint32_t tag);
  /// The index of a tag: kUntagged for "?" (and ""), kNonSpecific for "!".
  uint32_t TagIndex(std::string_view tag);
  static constexpr uint32_t kUntagged = 0, kNonSpecific = 1;
  void Close();
  /// A reference to an earlier node (an alias) as the next child.
  void AddAlias(uint32_t id) { Attach(id); }

 private:
  void Attach(uint32_t id) {
    if (!open_.empty()) pending_.push_back(id);
  }
  uint32_t Add(const Item& it) {
    const auto id = static_cast<uint32_t>(items_.size());
    items_.push_back(it);
    Attach(id);
    return id;
  }
  bool RepeatsAKey(uint32_t map) const;
  YamlNode Zombie(std::string_view key) const;
  friend class YamlNode;

  std::vector<Item> items_;
  std::string texts_;
  std::vector<std::string> tags_;
  std::vector<uint32_t> children_;
  /// Open collections, innermost last: (node, where its children start in pending_).
  std::vector<std::pair<uint32_t, size_t>> open_;
  std::vector<uint32_t> pending_;
  /// The keys looked up and not found (a few distinct ones per document: "shape", "unit", …),
  /// each kept once for the zombies' messages.
  mutable std::vector<std::string> missing_keys_;
  bool repeated_key_ = false;
};

// The accessors the loader calls for every node, inline: out of line, the calls alone were a
// visible part of walking the written-out chain (bench/RESULTS.md).
inline bool YamlNode::IsNull() const {
  CheckValid();
  return doc_->item(id_).kind == YamlDoc::Kind::kNull;
}
inline bool YamlNode::IsScalar() const {
  CheckValid();
  return doc_->item(id_).kind == YamlDoc::Kind::kScalar;
}
inline bool YamlNode::IsSequence() const {
  CheckValid();
  return doc_->item(id_).kind == YamlDoc::Kind::kSequence;
}
inline bool YamlNode::IsMap() const {
  CheckValid();
  return doc_->item(id_).kind == YamlDoc::Kind::kMap;
}
inline std::string_view YamlNode::Scalar() const {
  CheckValid();
  return doc_->item(id_).kind == YamlDoc::Kind::kScalar ? doc_->scalar(id_) : std::string_view();
}
inline const std::string& YamlNode::Tag() const {
  CheckValid();
  return doc_->tag(id_);
}
inline YamlMark YamlNode::Mark() const {
  CheckValid();
  return doc_->item(id_).mark;
}
inline size_t YamlNode::size() const {
  CheckValid();
  const YamlDoc::Item& it = doc_->item(id_);
  if (it.kind == YamlDoc::Kind::kSequence) return it.count;
  if (it.kind == YamlDoc::Kind::kMap) return it.count / 2;
  return 0;
}
inline YamlNode::Iterator YamlNode::begin() const { return Iterator(*this, 0); }
inline YamlNode::Iterator YamlNode::end() const {
  // Like yaml-cpp, an invalid node iterates as empty.
  return Iterator(*this, IsDefined() ? size() : 0);
}
inline YamlNode::Entry YamlNode::Iterator::operator*() const {
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

template <>
std::string YamlNode::as<std::string>() const;

/// The first document of a text as a reader gives it: `documents` is 0, 1 or 2, how many
/// documents were seen, stopping at the start of a second, which starts at `second_mark`, byte
/// `second_offset`; `stuck` says yaml-cpp's parser did not advance there.
struct ParsedYaml {
  std::unique_ptr<YamlDoc> doc;
  int documents = 0;
  YamlMark second_mark;
  size_t second_offset = 0;
  bool stuck = false;
};

}  // namespace momenta
