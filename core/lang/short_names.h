#pragma once
// The shorter names a qualified type name is found by. Standard library only: the build-time tool
// that embeds the component library (core/lang/embed_library.cc) uses it too, before momenta exists.

#include <algorithm>
#include <string>
#include <vector>

namespace momenta {

/// The shorter names a qualified type name is found by: its dotted tails, the last part alone only
/// for a package one level deep. `Rotational.Inertia` by `Inertia`; `MultiBody.Parts.Body` by
/// `Parts.Body` (the MSL's own spelling inside MultiBody), so that `Body` stays `Planar.Body`.
inline std::vector<std::string> ShortNames(const std::string& name) {
  std::vector<std::string> tails;
  const size_t dots = static_cast<size_t>(std::count(name.begin(), name.end(), '.'));
  for (size_t dot = name.find('.'); dot != std::string::npos; dot = name.find('.', dot + 1)) {
    const std::string tail = name.substr(dot + 1);
    if (tail.find('.') == std::string::npos && dots > 1) continue;
    tails.push_back(tail);
  }
  return tails;
}

}  // namespace momenta
