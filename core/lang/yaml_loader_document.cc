// A model or library file's text and its one YAML document (core/lang/yaml_loader_document.h).

#include "core/lang/yaml_loader_document.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/exceptions.h>

#include <algorithm>
#include <cstdint>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/base/regular_file.h"
#include "core/lang/yaml_document.h"

namespace momenta {

SourceLoc MarkLoc(const std::string& file, int line, int column) {
  SourceLoc loc;
  loc.set_file(file);
  if (line >= 0) {
    loc.line = line + 1;
    loc.column = column + 1;
  }
  return loc;
}

namespace {

/// Larger model files are refused before they are read whole (a model is a few kilobytes; the
/// largest benchmark model is under 2 KiB).
constexpr size_t kMaxModelFileBytes = size_t{256} << 20;

/// Where a mapping's key `k` was first given before (its index), or -1 when it is new. Small
/// mappings compare their keys pairwise; large ones (a model's 100 000 components) use a table.
class FirstKeys {
 public:
  explicit FirstKeys(size_t pairs) : hashed_(pairs > kPairwise) {
    if (hashed_) first_.reserve(pairs);
  }
  long Add(std::string_view key, size_t k) {
    if (hashed_) {
      auto [at, inserted] = first_.emplace(key, k);
      return inserted ? -1 : static_cast<long>(at->second);
    }
    for (size_t j = 0; j < keys_.size(); ++j) {
      if (keys_[j].first == key) return static_cast<long>(keys_[j].second);
    }
    keys_.emplace_back(key, k);
    return -1;
  }

 private:
  static constexpr size_t kPairwise = 16;
  bool hashed_;
  std::vector<std::pair<std::string_view, size_t>> keys_;
  std::unordered_map<std::string_view, size_t> first_;
};

/// A YAML mapping keeps every pair and looks a key up by its first occurrence, so a key
/// given twice would silently lose its second value: report it, with both places. The walk is
/// iterative and visits a node reached through several aliases once (alias bombs stay linear).
void CheckDuplicateKeys(const YamlDoc& doc, const std::string& file, const std::string& what) {
  // A node to walk: the collection it was reached from (an index into `walked`, kTop for the
  // root) and the key or element number it is there. Paths are spelled out for a message only.
  constexpr uint32_t kTop = ~0u;
  struct Step {
    YamlNode node;
    uint32_t parent;
    std::string_view key;  ///< under a mapping
    size_t element;        ///< under a sequence: 1-based
  };
  std::vector<Step> walked;  // the collections walked, in order
  std::vector<bool> seen(doc.num_nodes());
  auto path_of = [&](uint32_t at) {
    std::vector<const Step*> up;
    for (; at != kTop; at = walked[at].parent) up.push_back(&walked[at]);
    std::string path;
    for (auto s = up.rbegin(); s != up.rend(); ++s) {
      if ((*s)->parent == kTop) continue;
      // Appended piece by piece: `"[" + text` trips GCC 12's -Wrestrict (a false positive).
      if ((*s)->element > 0) {
        path += '[';
        path += std::to_string((*s)->element);
        path += ']';
      } else {
        if (!path.empty()) path += '.';
        path += (*s)->key;
      }
    }
    return path;
  };
  std::vector<Step> stack{{doc.root(), kTop, {}, 0}};
  while (!stack.empty()) {
    const Step step = stack.back();
    stack.pop_back();
    const YamlNode node = step.node;
    if (!node.IsMap() && !node.IsSequence()) continue;
    if (seen[node.id()]) continue;
    seen[node.id()] = true;
    const auto here = static_cast<uint32_t>(walked.size());
    walked.push_back(step);
    const size_t n = node.size();
    // The children, walked in the order of the file (pushed last to first).
    const size_t bottom = stack.size();
    if (node.IsSequence()) {
      for (size_t k = n; k-- > 0;) stack.push_back({node[k], here, {}, k + 1});
      continue;
    }
    FirstKeys first(n);
    size_t k = 0;
    for (auto it = node.begin(); it != node.end(); ++it, ++k) {
      if (!it->first.IsScalar()) continue;
      const std::string_view key = it->first.Scalar();
      const long before = first.Add(key, k);
      if (before >= 0) {
        const YamlMark at = (*YamlNode::Iterator(node, static_cast<size_t>(before))).first.Mark();
        const std::string path = path_of(here);
        throw ModelError(MarkLoc(file, it->first.Mark()),
                         "'" + std::string(key) + "' is given twice in " +
                             (path.empty() ? "the " + what : path) + " (first at line " +
                             std::to_string(at.line + 1) + ", column " +
                             std::to_string(at.column + 1) + "); remove one of them");
      }
      stack.push_back({it->second, here, key, 0});
    }
    std::reverse(stack.begin() + static_cast<std::ptrdiff_t>(bottom), stack.end());
  }
}

}  // namespace

std::unique_ptr<YamlDoc> ParseYamlFile(const std::string& text, const std::string& file,
                                       const std::string& what) {
  ParsedYaml parsed;
  try {
    parsed = ParseYamlDocument(text);
  } catch (const YAML::DeepRecursion& e) {
    throw ModelError(
        MarkLoc(file, e.mark.line, e.mark.column),
        "YAML nested too deeply: lists and mappings nested hundreds of levels deep are "
        "not read (a " +
            what + " needs a few levels)");
  } catch (const YAML::Exception& e) {
    throw ModelError(MarkLoc(file, e.mark.line, e.mark.column), "YAML syntax error: " + e.msg);
  }
  if (parsed.documents == 2) {
    // yaml-cpp's parser does not consume a ',' where a document should start (0.7: the input ",").
    if (parsed.stuck) {
      throw ModelError(
          MarkLoc(file, parsed.second_mark),
          "YAML syntax error: unexpected '" + text.substr(parsed.second_offset, 1) + "'");
    }
    throw ModelError(MarkLoc(file, parsed.second_mark),
                     "a second YAML document starts here; a " + what + " holds one document");
  }
  if (parsed.documents == 0 || !parsed.doc || parsed.doc->empty()) {
    bool blank = text.find_first_not_of(" \t\r\n") == std::string::npos;
    throw ModelError(SourceLoc(file),
                     "the " + what + " is empty" + (blank ? "" : " (it holds only comments)"));
  }
  if (parsed.doc->has_repeated_key()) CheckDuplicateKeys(*parsed.doc, file, what);
  return std::move(parsed.doc);
}

std::string ReadModelText(const std::string& path, const char* what) {
  // Anything but a regular file is refused before a byte is read: a FIFO would block for ever and
  // a device (/dev/zero) never ends.
  try {
    return RegularFile(path, what, kMaxModelFileBytes, "; a model is a short text").ReadAll();
  } catch (const FileRefused& e) {
    throw ModelError(e.what());
  }
}

}  // namespace momenta
