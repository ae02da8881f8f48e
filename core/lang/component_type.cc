// Component and connector types (core/lang/component_type.h): a connection end's tree made when
// it is needed, and the library's lookup by full or short name.

#include "core/lang/component_type.h"

#include <algorithm>

#include "core/lang/parser.h"

namespace momenta {

AstPtr ConnectionSpec::EndA() const { return a ? a : ParseName(a_text, a_loc); }
AstPtr ConnectionSpec::EndB() const { return b ? b : ParseName(b_text, b_loc); }

const char* ValueTypeName(ValueType t) {
  switch (t) {
    case ValueType::kReal: return "Real";
    case ValueType::kInteger: return "Integer";
    case ValueType::kBoolean: return "Boolean";
  }
  return "?";
}

namespace {

/// Records `name` under its dotted tails (ShortNames); a short name that two qualified names
/// share maps to "" (ambiguous: the full name is needed).
void AddShortName(const std::string& name, std::map<std::string, std::string>* short_names) {
  for (const std::string& tail : ShortNames(name)) {
    auto [it, inserted] = short_names->emplace(tail, name);
    if (!inserted && it->second != name) it->second.clear();
  }
}

/// The entry named `name`, or the one whose qualified name it abbreviates.
template <typename T>
const T* FindQualified(const std::map<std::string, std::shared_ptr<T>>& entries,
                       const std::map<std::string, std::string>& short_names, const std::string& name) {
  auto it = entries.find(name);
  if (it != entries.end()) return it->second.get();
  auto s = short_names.find(name);
  if (s == short_names.end() || s->second.empty()) return nullptr;
  it = entries.find(s->second);
  return it == entries.end() ? nullptr : it->second.get();
}


/// The one entry whose name ends in `.name` (`Orientation` for `MultiBody.Orientation`,
/// `Frames.resolve2` for `MultiBody.Frames.resolve2`), or null for none or several.
template <typename T>
const T* FindByTail(const std::map<std::string, std::shared_ptr<T>>& entries, const std::string& name) {
  const T* found = nullptr;
  for (const auto& [full, entry] : entries) {
    if (full.size() > name.size() && full.compare(full.size() - name.size(), name.size(), name) == 0 &&
        full[full.size() - name.size() - 1] == '.') {
      if (found) return nullptr;
      found = entry.get();
    }
  }
  return found;
}

}  // namespace

Library::Library(const Library& other) { *this = other; }

Library& Library::operator=(const Library& other) {
  if (this == &other) return *this;
  if (other.lazy_) other.lazy_->ReadAll(const_cast<Library*>(&other));
  connectors_ = other.connectors_;
  components_ = other.components_;
  short_connectors_ = other.short_connectors_;
  short_components_ = other.short_components_;
  records_ = other.records_;
  functions_ = other.functions_;
  short_functions_ = other.short_functions_;
  lazy_ = nullptr;
  base_ = other.base_;
  return *this;
}

void Library::AddConnector(ConnectorType c) {
  std::string name = c.name;
  AddShortName(name, &short_connectors_);
  connectors_[name] = std::make_shared<ConnectorType>(std::move(c));
}

void Library::AddComponent(ComponentType c) {
  std::string name = c.name;
  AddShortName(name, &short_components_);
  components_[name] = std::make_shared<ComponentType>(std::move(c));
}

const ConnectorType* Library::FindConnector(const std::string& name) const {
  const ConnectorType* c = FindQualified(connectors_, short_connectors_, name);
  return c || !base_ ? c : base_->FindConnector(name);
}

void Library::AddRecord(RecordType r) {
  std::string name = r.name;
  records_[name] = std::make_shared<RecordType>(std::move(r));
}

void Library::AddFunction(FunctionDecl f) {
  std::string name = f.name;
  AddShortName(name, &short_functions_);
  functions_[name] = std::make_shared<FunctionDecl>(std::move(f));
}

const RecordType* Library::FindRecord(const std::string& name) const {
  auto it = records_.find(name);
  const RecordType* r = it != records_.end() ? it->second.get() : FindByTail(records_, name);
  return r || !base_ ? r : base_->FindRecord(name);
}

const FunctionDecl* Library::FindFunction(const std::string& name) const {
  if (const FunctionDecl* f = FindQualified(functions_, short_functions_, name)) return f;
  if (const FunctionDecl* f = FindByTail(functions_, name)) return f;
  if (lazy_) {
    lazy_->ReadFunctions(const_cast<Library*>(this));
    if (const FunctionDecl* f = FindQualified(functions_, short_functions_, name)) return f;
    if (const FunctionDecl* f = FindByTail(functions_, name)) return f;
  }
  return base_ ? base_->FindFunction(name) : nullptr;
}

void Library::AddRecordsAndFunctions(const Library& other) {
  for (const auto& [name, r] : other.records_) records_[name] = r;
  for (const auto& [name, f] : other.functions_) {
    AddShortName(name, &short_functions_);
    functions_[name] = f;
  }
}

void Library::AddOwnEntries(const Library& other) {
  AddRecordsAndFunctions(other);
  for (const auto& [name, c] : other.connectors_) {
    AddShortName(name, &short_connectors_);
    connectors_[name] = c;
  }
}

void Library::ReadLazily(const std::string& name) const {
  if (lazy_) lazy_->Read(name, const_cast<Library*>(this));
}

const ComponentType* Library::FindComponent(const std::string& name) const {
  // Not yet read: the source reads the type of that exact name and every type it could abbreviate,
  // so that the short-name rule below sees what it would see in the whole library.
  if (!components_.count(name)) ReadLazily(name);
  const ComponentType* t = FindQualified(components_, short_components_, name);
  return t || !base_ ? t : base_->FindComponent(name);
}

bool Library::Has(const std::string& name) const {
  if (!connectors_.count(name) && !components_.count(name)) ReadLazily(name);
  return connectors_.count(name) || components_.count(name) || (base_ && base_->Has(name));
}

bool Library::HasComponent(const std::string& name) const {
  if (!components_.count(name)) ReadLazily(name);
  return components_.count(name) != 0 || (base_ && base_->HasComponent(name));
}

std::vector<std::string> Library::ComponentNames() const {
  if (lazy_) lazy_->ReadAll(const_cast<Library*>(this));
  std::vector<std::string> out = base_ ? base_->ComponentNames() : std::vector<std::string>();
  for (const auto& [name, t] : components_) out.push_back(name);
  return out;
}

std::vector<std::string> Library::RecordNames() const {
  std::vector<std::string> out = base_ ? base_->RecordNames() : std::vector<std::string>();
  for (const auto& [name, r] : records_) out.push_back(name);
  return out;
}

std::vector<std::string> Library::ConnectorNames() const {
  std::vector<std::string> out = base_ ? base_->ConnectorNames() : std::vector<std::string>();
  for (const auto& [name, t] : connectors_) out.push_back(name);
  return out;
}

}  // namespace momenta
