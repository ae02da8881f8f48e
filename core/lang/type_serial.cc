// A component type as bytes and back (type_serial.h).
//
// One function per struct lists its fields (Io below); the writer and the reader both go through
// it, so the two cannot disagree on the order. The bytes are: the file names the locations use,
// the expression nodes (each after its children, so a node refers to earlier ones by number; a
// subtree shared by two fields is one node), then the fields. Numbers are stored as the machine
// holds them: the bytes never leave the binary that wrote them.

#include "core/lang/type_serial.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>
#include <vector>

namespace momenta {

namespace {

// A new field in one of these structs must be added to its Io function below: the sizes are
// checked where they are known (x86-64, libstdc++), so that a field cannot be left out unnoticed.
#if defined(__x86_64__) && defined(__GLIBCXX__)
static_assert(sizeof(Ast) == 104, "a field added to Ast: add it to Writer::NodeId and Reader::ReadNode");
static_assert(sizeof(ParameterDecl) == 224, "a field added to ParameterDecl: add it to its Io");
static_assert(sizeof(VariableDecl) == 240, "a field added to VariableDecl: add it to its Io");
static_assert(sizeof(EquationDecl) == 128, "a field added to EquationDecl: add it to its Io");
static_assert(sizeof(StatementDecl) == 104, "a field added to StatementDecl: add it to its Io");
static_assert(sizeof(WhenDecl) == 88, "a field added to WhenDecl: add it to its Io");
static_assert(sizeof(ImpactDecl) == 320, "a field added to ImpactDecl: add it to its Io");
static_assert(sizeof(ShapeField) == 120, "a field added to ShapeField: add it to its Io");
static_assert(sizeof(ShapeDecl) == 80, "a field added to ShapeDecl: add it to its Io");
static_assert(sizeof(ConnectorDecl) == 168, "a field added to ConnectorDecl: add it to its Io");
static_assert(sizeof(Modifier) == 216, "a field added to Modifier: add it to its Io");
static_assert(sizeof(ComponentSpec) == 224, "a field added to ComponentSpec: add it to its Io");
static_assert(sizeof(ConnectionSpec) == 240, "a field added to ConnectionSpec: add it to its Io");
static_assert(sizeof(GraphDecl) == 120, "a field added to GraphDecl: add it to its Io");
static_assert(sizeof(ConnectorVariable) == 160, "a field added to ConnectorVariable: add it to its Io");
static_assert(sizeof(RecordType) == 104, "a field added to RecordType: add it to its Io");
static_assert(sizeof(ConnectorType) == 232, "a field added to ConnectorType: add it to its Io");
static_assert(sizeof(FunctionDecl) == 232, "a field added to FunctionDecl: add it to its Io");
static_assert(sizeof(FunctionDecl::Input) == 88, "a field added to FunctionDecl::Input: add it to its Io");
static_assert(sizeof(ComponentType) == 600, "a field added to ComponentType: add it to its Io");
#endif

/// Writes the bytes: the fields as Io visits them, the nodes and file names into their own parts.
class Writer {
 public:
  static constexpr bool kReading = false;

  void Raw(const void* p, size_t n) { fields_.append(static_cast<const char*>(p), n); }
  template <class T>
  void Number(const T* v) {
    Raw(v, sizeof *v);
  }
  void Count(const uint32_t* n) { Number(n); }
  void Text(const std::string* s) {
    const auto n = static_cast<uint32_t>(s->size());
    Number(&n);
    Raw(s->data(), s->size());
  }
  void Node(const AstPtr* a) {
    const uint32_t id = NodeId(*a);
    Number(&id);
  }
  void Location(const SourceLoc* loc) {
    const auto [at, added] = files_.emplace(loc->file(), static_cast<uint32_t>(file_names_.size()));
    if (added) file_names_.push_back(loc->file());
    Number(&at->second);
    Number(&loc->line);
    Number(&loc->column);
  }

  std::string Finish() {
    std::string out;
    const auto put = [&out](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
    const auto files = static_cast<uint32_t>(file_names_.size());
    put(&files, sizeof files);
    for (const std::string& f : file_names_) {
      const auto n = static_cast<uint32_t>(f.size());
      put(&n, sizeof n);
      put(f.data(), f.size());
    }
    put(&node_count_, sizeof node_count_);
    out += nodes_;
    out += fields_;
    return out;
  }

 private:
  /// The node's number (0 for none), written after its children's the first time it is met.
  uint32_t NodeId(const AstPtr& a) {
    if (!a) return 0;
    if (auto it = ids_.find(a.get()); it != ids_.end()) return it->second;
    std::vector<uint32_t> segments;
    for (const NameSegment& s : a->path) {
      segments.push_back(NodeId(s.index));
      segments.push_back(NodeId(s.index2));
    }
    std::vector<uint32_t> args;
    for (const AstPtr& arg : a->args) args.push_back(NodeId(arg));
    std::string& out = nodes_;
    const auto put = [&out](const auto& v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); };
    const auto text = [&out, &put](const std::string& s) {
      put(static_cast<uint32_t>(s.size()));
      out += s;
    };
    put(static_cast<uint8_t>(a->kind));
    put(a->number);
    put(static_cast<uint32_t>(a->path.size()));
    for (size_t k = 0; k < a->path.size(); ++k) {
      text(a->path[k].name);
      put(segments[2 * k]);
      put(segments[2 * k + 1]);
    }
    text(a->op);
    put(static_cast<uint32_t>(args.size()));
    for (uint32_t id : args) put(id);
    put(a->column);
    put(a->height);
    ids_.emplace(a.get(), ++node_count_);
    return node_count_;
  }

  std::string fields_, nodes_;
  uint32_t node_count_ = 0;
  std::unordered_map<const Ast*, uint32_t> ids_;
  std::map<std::string, uint32_t> files_;
  std::vector<std::string> file_names_;
};

/// Reads the bytes Writer wrote, checking that nothing runs past their end.
class Reader {
 public:
  static constexpr bool kReading = true;

  explicit Reader(std::string_view bytes) : at_(bytes.data()), end_(bytes.data() + bytes.size()) {
    uint32_t files = 0;
    Number(&files);
    for (uint32_t k = 0; k < files; ++k) {
      std::string name;
      Text(&name);
      locations_.emplace_back(name);
    }
    uint32_t nodes = 0;
    Number(&nodes);
    Need(nodes);  // at least a byte a node: a count past the end is refused before reserving
    nodes_.reserve(nodes);
    for (uint32_t k = 0; k < nodes; ++k) nodes_.push_back(ReadNode());
  }

  void Raw(void* p, size_t n) {
    Need(n);
    std::memcpy(p, at_, n);
    at_ += n;
  }
  template <class T>
  void Number(T* v) {
    Raw(v, sizeof *v);
  }
  /// A flag is a byte 0 or 1: any other byte is refused, not loaded into a bool.
  void Number(bool* v) {
    uint8_t byte = 0;
    Raw(&byte, 1);
    if (byte > 1) throw std::runtime_error("compiled type: a flag that is neither 0 nor 1");
    *v = byte != 0;
  }
  void Count(uint32_t* n) {
    Number(n);
    Need(*n);  // every element takes at least a byte
  }
  void Text(std::string* s) {
    uint32_t n = 0;
    Number(&n);
    Need(n);
    s->assign(at_, n);
    at_ += n;
  }
  void Node(AstPtr* a) {
    uint32_t id = 0;
    Number(&id);
    *a = NodeAt(id);
  }
  void Location(SourceLoc* loc) {
    uint32_t file = 0;
    Number(&file);
    if (file >= locations_.size()) throw std::runtime_error("compiled type: a file number past the table");
    *loc = locations_[file];
    Number(&loc->line);
    Number(&loc->column);
  }
  bool done() const { return at_ == end_; }

 private:
  void Need(size_t n) const {
    if (static_cast<size_t>(end_ - at_) < n) throw std::runtime_error("compiled type: the bytes end early");
  }
  AstPtr NodeAt(uint32_t id) const {
    if (id > nodes_.size()) throw std::runtime_error("compiled type: a node refers to a later one");
    return id == 0 ? nullptr : nodes_[id - 1];
  }
  AstPtr ReadNode() {
    auto a = std::make_shared<Ast>();
    uint8_t kind = 0;
    Number(&kind);
    if (kind > static_cast<uint8_t>(Ast::Kind::kArray)) throw std::runtime_error("compiled type: an unknown node kind");
    a->kind = static_cast<Ast::Kind>(kind);
    Number(&a->number);
    uint32_t segments = 0;
    Count(&segments);
    a->path.resize(segments);
    for (NameSegment& s : a->path) {
      Text(&s.name);
      uint32_t index = 0, index2 = 0;
      Number(&index);
      Number(&index2);
      s.index = NodeAt(index);
      s.index2 = NodeAt(index2);
    }
    Text(&a->op);
    uint32_t args = 0;
    Count(&args);
    a->args.resize(args);
    for (AstPtr& arg : a->args) {
      uint32_t id = 0;
      Number(&id);
      arg = NodeAt(id);
    }
    Number(&a->column);
    Number(&a->height);
    return a;
  }

  const char* at_;
  const char* end_;
  std::vector<SourceLoc> locations_;  ///< one per file name, line and column 0
  std::vector<AstPtr> nodes_;
};

// The fields of each struct, in one order for writing and reading.
template <class A> void Io(A& a, std::string& s) { a.Text(&s); }
template <class A> void Io(A& a, AstPtr& p) { a.Node(&p); }
template <class A> void Io(A& a, SourceLoc& loc) { a.Location(&loc); }
template <class A, class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
void Io(A& a, T& v) {
  a.Number(&v);
}
template <class A, class T, std::enable_if_t<std::is_enum_v<T>, int> = 0>
void Io(A& a, T& v) {
  a.Number(&v);
}
template <class A, class T> void Io(A& a, std::vector<T>& v);
template <class A, class T> void Io(A& a, std::optional<T>& v);
template <class A, class K, class V> void Io(A& a, std::map<K, V>& m);
template <class A> void Io(A& a, AstEquation& e);
template <class A> void Io(A& a, BlockBranch& b);
template <class A> void Io(A& a, ParameterDecl& p);
template <class A> void Io(A& a, VariableDecl& v);
template <class A> void Io(A& a, EquationDecl& e);
template <class A> void Io(A& a, StatementDecl& s);
template <class A> void Io(A& a, WhenDecl& w);
template <class A> void Io(A& a, ImpactDecl& i);
template <class A> void Io(A& a, ShapeField& f);
template <class A> void Io(A& a, ShapeDecl& s);
template <class A> void Io(A& a, ConnectorDecl& c);
template <class A> void Io(A& a, Modifier& m);
template <class A> void Io(A& a, ComponentSpec& c);
template <class A> void Io(A& a, ConnectionSpec& c);
template <class A> void Io(A& a, GraphDecl& g);
template <class A> void Io(A& a, ConnectorVariable& v);
template <class A> void Io(A& a, FunctionDecl::Input& i);
template <class A, class T> void Io(A& a, std::pair<std::string, T>& p);

template <class A, class T>
void Io(A& a, std::vector<T>& v) {
  auto n = static_cast<uint32_t>(v.size());
  a.Count(&n);
  if constexpr (A::kReading) v.resize(n);
  for (T& x : v) Io(a, x);
}

template <class A, class T>
void Io(A& a, std::optional<T>& v) {
  bool has = v.has_value();
  Io(a, has);
  if constexpr (A::kReading) {
    if (has) v.emplace();
  }
  if (has) Io(a, *v);
}

template <class A, class K, class V>
void Io(A& a, std::map<K, V>& m) {
  auto n = static_cast<uint32_t>(m.size());
  a.Count(&n);
  if constexpr (A::kReading) {
    for (uint32_t k = 0; k < n; ++k) {
      std::pair<K, V> entry;
      Io(a, entry.first);
      Io(a, entry.second);
      m.insert(std::move(entry));
    }
  } else {
    for (auto& [key, value] : m) {
      K copy = key;
      Io(a, copy);
      Io(a, value);
    }
  }
}

template <class A> void Io(A& a, AstEquation& e) {
  Io(a, e.lhs);
  Io(a, e.rhs);
}
template <class A> void Io(A& a, BlockBranch& b) {
  Io(a, b.block);
  Io(a, b.branch);
}
template <class A> void Io(A& a, ParameterDecl& p) {
  Io(a, p.name); Io(a, p.value); Io(a, p.value_text); Io(a, p.unit); Io(a, p.doc); Io(a, p.min); Io(a, p.max);
  Io(a, p.type); Io(a, p.shape); Io(a, p.evaluate); Io(a, p.loc);
}
template <class A> void Io(A& a, VariableDecl& v) {
  Io(a, v.name); Io(a, v.unit); Io(a, v.doc); Io(a, v.start); Io(a, v.fixed); Io(a, v.nominal); Io(a, v.min);
  Io(a, v.max); Io(a, v.state_priority); Io(a, v.type); Io(a, v.shape); Io(a, v.record); Io(a, v.counted);
  Io(a, v.loc);
}
template <class A> void Io(A& a, EquationDecl& e) {
  Io(a, e.text); Io(a, e.ast); Io(a, e.loc); Io(a, e.guard); Io(a, e.blocks); Io(a, e.counted);
}
template <class A> void Io(A& a, StatementDecl& s) {
  Io(a, s.is_reinit); Io(a, s.target); Io(a, s.value); Io(a, s.text); Io(a, s.loc);
}
template <class A> void Io(A& a, WhenDecl& w) {
  Io(a, w.text); Io(a, w.condition); Io(a, w.statements); Io(a, w.loc);
}
template <class A> void Io(A& a, ImpactDecl& i) {
  Io(a, i.gap); Io(a, i.velocity); Io(a, i.restitution); Io(a, i.v_small); Io(a, i.release);
  Io(a, i.gap_text); Io(a, i.velocity_text); Io(a, i.restitution_text); Io(a, i.v_small_text);
  Io(a, i.release_text); Io(a, i.force); Io(a, i.contact); Io(a, i.loc);
}
template <class A> void Io(A& a, ShapeField& f) {
  Io(a, f.key); Io(a, f.text); Io(a, f.expr); Io(a, f.shape); Io(a, f.loc);
}
template <class A> void Io(A& a, ShapeDecl& s) {
  Io(a, s.kind); Io(a, s.space); Io(a, s.fields); Io(a, s.loc);
}
template <class A> void Io(A& a, ConnectorDecl& c) {
  Io(a, c.name); Io(a, c.type); Io(a, c.doc); Io(a, c.shape); Io(a, c.condition); Io(a, c.loc);
}
template <class A> void Io(A& a, Modifier& m) {
  Io(a, m.key); Io(a, m.value); Io(a, m.value_text); Io(a, m.value_unit); Io(a, m.start); Io(a, m.fixed);
  Io(a, m.state_priority); Io(a, m.nominal); Io(a, m.min); Io(a, m.max); Io(a, m.loc); Io(a, m.key_loc);
}
template <class A> void Io(A& a, ComponentSpec& c) {
  Io(a, c.name); Io(a, c.type); Io(a, c.doc); Io(a, c.count); Io(a, c.condition); Io(a, c.condition_text);
  Io(a, c.condition_loc); Io(a, c.modifiers); Io(a, c.loc); Io(a, c.type_loc);
}
template <class A> void Io(A& a, ConnectionSpec& c) {
  Io(a, c.a); Io(a, c.b); Io(a, c.a_text); Io(a, c.b_text); Io(a, c.loop_var); Io(a, c.loop_from);
  Io(a, c.loop_to); Io(a, c.loop_text); Io(a, c.loop_loc); Io(a, c.loc); Io(a, c.a_loc); Io(a, c.b_loc);
}
template <class A> void Io(A& a, GraphDecl& g) {
  Io(a, g.a); Io(a, g.b); Io(a, g.priority); Io(a, g.condition); Io(a, g.loc);
}
template <class A> void Io(A& a, ConnectorVariable& v) {
  Io(a, v.name); Io(a, v.unit); Io(a, v.doc); Io(a, v.shape); Io(a, v.record); Io(a, v.counted);
}
template <class A> void Io(A& a, FunctionDecl::Input& i) {
  Io(a, i.name); Io(a, i.shape); Io(a, i.record);
}
template <class A, class T> void Io(A& a, std::pair<std::string, T>& p) {
  Io(a, p.first); Io(a, p.second);
}
template <class A> void Io(A& a, RecordType& r) {
  Io(a, r.name); Io(a, r.doc); Io(a, r.fields); Io(a, r.residues); Io(a, r.loc);
}
template <class A> void Io(A& a, ConnectorType& c) {
  Io(a, c.name); Io(a, c.doc); Io(a, c.is_signal); Io(a, c.is_input); Io(a, c.signal_type); Io(a, c.potentials);
  Io(a, c.flows); Io(a, c.arrays); Io(a, c.records); Io(a, c.loc);
}
template <class A> void Io(A& a, FunctionDecl& f) {
  Io(a, f.name); Io(a, f.doc); Io(a, f.inputs); Io(a, f.value); Io(a, f.value_text); Io(a, f.record); Io(a, f.fields);
  Io(a, f.field_texts); Io(a, f.loc);
}
template <class A> void Io(A& a, ComponentType& t) {
  Io(a, t.name); Io(a, t.doc); Io(a, t.parameters); Io(a, t.tables); Io(a, t.connectors); Io(a, t.variables);
  Io(a, t.equations); Io(a, t.initial_equations); Io(a, t.whens); Io(a, t.impacts); Io(a, t.animation);
  Io(a, t.components); Io(a, t.connections); Io(a, t.arrays); Io(a, t.outers); Io(a, t.roots);
  Io(a, t.potential_roots); Io(a, t.branches); Io(a, t.blocks); Io(a, t.records); Io(a, t.uncounted_equations);
  Io(a, t.scalar_form); Io(a, t.loc); Io(a, t.user_defined);
}

/// What the library holds before any type is read: its records and connector types.
struct LibraryStart {
  std::vector<RecordType> records;
  std::vector<ConnectorType> connectors;
};
template <class A> void Io(A& a, LibraryStart& s) {
  Io(a, s.records); Io(a, s.connectors);
}

/// `value` as bytes.
template <class T>
std::string Serialize(const T& value) {
  Writer writer;
  // The writer only reads the fields: Io takes them by reference so that the reader can share it.
  Io(writer, const_cast<T&>(value));
  return writer.Finish();
}

/// The value Serialize wrote into `bytes`.
template <class T>
T Deserialize(std::string_view bytes) {
  Reader reader(bytes);
  T value;
  Io(reader, value);
  if (!reader.done()) throw std::runtime_error("compiled type: bytes left after the type");
  return value;
}

}  // namespace

std::string SerializeComponentType(const ComponentType& type) { return Serialize(type); }
ComponentType DeserializeComponentType(std::string_view bytes) { return Deserialize<ComponentType>(bytes); }
std::string SerializeFunction(const FunctionDecl& function) { return Serialize(function); }
FunctionDecl DeserializeFunction(std::string_view bytes) { return Deserialize<FunctionDecl>(bytes); }

std::string SerializeRecordsAndConnectors(const Library& library) {
  LibraryStart start;
  for (const std::string& name : library.RecordNames()) start.records.push_back(*library.FindRecord(name));
  for (const std::string& name : library.ConnectorNames()) start.connectors.push_back(*library.FindConnector(name));
  return Serialize(start);
}

void DeserializeRecordsAndConnectors(std::string_view bytes, Library* library) {
  LibraryStart start = Deserialize<LibraryStart>(bytes);
  for (RecordType& r : start.records) library->AddRecord(std::move(r));
  for (ConnectorType& c : start.connectors) library->AddConnector(std::move(c));
}

}  // namespace momenta
