#include "core/component_type.h"

#include <algorithm>

namespace momenta {

const char* ValueTypeName(ValueType t) {
  switch (t) {
    case ValueType::kReal: return "Real";
    case ValueType::kInteger: return "Integer";
    case ValueType::kBoolean: return "Boolean";
  }
  return "?";
}

void Library::AddConnector(ConnectorType c) {
  std::string name = c.name;
  connectors_[name] = std::make_shared<ConnectorType>(std::move(c));
}

void Library::AddComponent(ComponentType c) {
  std::string name = c.name;
  components_[name] = std::make_shared<ComponentType>(std::move(c));
}

const ConnectorType* Library::FindConnector(const std::string& name) const {
  auto it = connectors_.find(name);
  return it == connectors_.end() ? nullptr : it->second.get();
}

const ComponentType* Library::FindComponent(const std::string& name) const {
  auto it = components_.find(name);
  return it == components_.end() ? nullptr : it->second.get();
}

bool Library::Has(const std::string& name) const {
  return connectors_.count(name) || components_.count(name);
}

std::vector<std::string> Library::ComponentNames() const {
  std::vector<std::string> out;
  for (const auto& [name, t] : components_) out.push_back(name);
  return out;
}

std::vector<std::string> Library::ConnectorNames() const {
  std::vector<std::string> out;
  for (const auto& [name, t] : connectors_) out.push_back(name);
  return out;
}

std::string JoinNames(const std::vector<std::string>& names, size_t limit) {
  std::string s;
  for (size_t i = 0; i < names.size() && i < limit; ++i) {
    if (i) s += ", ";
    s += names[i];
  }
  if (names.size() > limit) s += ", …";
  return s;
}

namespace {
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t sub = prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}
}  // namespace

std::vector<std::string> ClosestNames(const std::string& wanted,
                                      const std::vector<std::string>& candidates) {
  std::vector<std::pair<size_t, std::string>> scored;
  for (const auto& c : candidates) {
    size_t d = EditDistance(wanted, c);
    if (d <= std::max<size_t>(2, wanted.size() / 3)) scored.emplace_back(d, c);
  }
  std::sort(scored.begin(), scored.end());
  std::vector<std::string> out;
  for (size_t i = 0; i < scored.size() && i < 3; ++i) out.push_back(scored[i].second);
  return out;
}

}  // namespace momenta
