// A build-time tool (not part of momenta): writes builtin_library_data.inc, the component library
// (components/*.yaml) as C++ for core/lang/builtin_library.cc.
//
//   momenta_embed_library OUTPUT FILE...     (each FILE given as components/NAME.yaml, relative to
//                                             the working directory)
//
// It holds each file's text as a raw string literal and the table of the files' top-level entries
// (one a type: its name, file, offset, length, first line and kind) with every short name of
// them, sorted, all numbers (no pointer to relocate at start), so that start-up looks a type up
// without cutting or scanning the text (cutting ~500 KB at every start was a tenth of a small
// model's whole run). An entry starts at a line that starts with a letter (its key, up to the
// first ':'); comments, indented and blank lines belong to the entry above. connectors.yaml is
// read whole at start and has no entries.
//
// Plain C++17 and the standard library only: it runs on the build machine before momenta exists.

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/lang/short_names.h"
#include "core/lang/write_if_changed.h"

namespace {

struct Entry {
  std::string name;
  size_t file = 0;
  size_t offset = 0;
  size_t length = 0;
  size_t line = 1;
  char kind = 't';
};

/// 'f' a function, 'r' a record, 'k' another entry with a kind (a connector type), both read at
/// start; 't' a component type, read on first use.
char KindOf(const std::string& text) {
  if (text.find("\n  kind: function") != std::string::npos) return 'f';
  if (text.find("\n  kind:") == std::string::npos) return 't';
  return text.find("\n  kind: record") != std::string::npos ? 'r' : 'k';
}

/// `s` as a C++ string literal ('\0' as an escape; a literal of its own ends each escape).
std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '\0') {
      out += "\\0\" \"";
      continue;
    }
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

/// Cuts `text` (file number `file`) into its top-level entries, appended to `entries`.
void Cut(const std::string& text, size_t file, std::vector<Entry>* entries) {
  Entry* open = nullptr;
  size_t line = 1;
  for (size_t at = 0; at < text.size(); ++line) {
    size_t end = text.find('\n', at);
    end = end == std::string::npos ? text.size() : end + 1;
    const char c = text[at];
    if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')) {
      if (open) open->length = at - open->offset;
      entries->push_back(Entry{text.substr(at, text.find(':', at) - at), file, at, 0, line, 't'});
      open = &entries->back();
    }
    at = end;
  }
  if (open) open->length = text.size() - open->offset;
  for (Entry& e : *entries) {
    if (e.file == file) e.kind = KindOf(text.substr(e.offset, e.length));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: momenta_embed_library OUTPUT components/NAME.yaml...\n";
    return 2;
  }
  std::vector<std::string> names(argv + 2, argv + argc);
  std::sort(names.begin(), names.end());
  std::ostringstream out;
  std::vector<Entry> entries;
  // FNV-1a over every file's name and text: the compiled types (core/lang/compiled_types.cc) are
  // used only with the text they were compiled from.
  uint64_t hash = 1469598103934665603ull;
  const auto mix = [&hash](const std::string& bytes) {
    for (const unsigned char c : bytes) hash = (hash ^ c) * 1099511628211ull;
    hash = (hash ^ 0xff) * 1099511628211ull;
  };
  out << "static const EmbeddedFile kEmbeddedLibraryFiles[] = {\n";
  for (size_t f = 0; f < names.size(); ++f) {
    std::ifstream in(names[f], std::ios::binary);
    if (!in) {
      std::cerr << names[f] << ": cannot be read\n";
      return 1;
    }
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find(")momenta_yaml\"") != std::string::npos) {
      std::cerr << names[f] << ": holds the raw string's end marker )momenta_yaml\"\n";
      return 1;
    }
    out << "  {" << Quoted(names[f]) << ", R\"momenta_yaml(" << text << ")momenta_yaml\"},\n";
    mix(names[f]);
    mix(text);
    if (names[f] != "components/connectors.yaml") Cut(text, f, &entries);
  }
  out << "};\n\n";
  out << "static constexpr uint64_t kEmbeddedLibraryHash = " << hash << "ull;\n\n";
  // Sorted by name (std::string's order, as a std::map of the names iterates); a name defined
  // twice would make which one a model gets depend on the files' order.
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.name < b.name; });
  for (size_t i = 1; i < entries.size(); ++i) {
    if (entries[i].name == entries[i - 1].name) {
      std::cerr << names[entries[i].file] << ":" << entries[i].line << ": " << entries[i].name
                << " is defined already in " << names[entries[i - 1].file] << "\n";
      return 1;
    }
  }
  // The names, each ended by '\0', in one literal, and numbers only in the tables: a pointer in a
  // table would be relocated at every start (its pages written, whether a run reads them or not).
  std::vector<size_t> name_at;
  out << "static const char kEmbeddedLibraryNames[] =\n";
  size_t pool = 0;
  for (const Entry& e : entries) {
    name_at.push_back(pool);
    out << "  " << Quoted(e.name + '\0') << "\n";
    pool += e.name.size() + 1;
  }
  out << "  \"\";\n\n";
  out << "static const EmbeddedEntry kEmbeddedLibraryEntries[] = {\n";
  for (size_t i = 0; i < entries.size(); ++i) {
    const Entry& e = entries[i];
    out << "  {" << name_at[i] << ", " << e.file << ", " << e.offset << ", " << e.length << ", "
        << e.line << ", '" << e.kind << "'},\n";
  }
  out << "};\n\n";
  // Short name -> the entries (indices above) that end in it, in the files' order; a short name
  // is the tail of its entry's name in the pool.
  std::vector<Entry> in_file_order = entries;
  std::stable_sort(in_file_order.begin(), in_file_order.end(), [](const Entry& a, const Entry& b) {
    return a.file != b.file ? a.file < b.file : a.offset < b.offset;
  });
  std::map<std::string, std::vector<std::pair<size_t, size_t>>>
      by_tail;  // tail -> (entry, pool offset)
  for (const Entry& e : in_file_order) {
    const size_t index = static_cast<size_t>(
        std::lower_bound(entries.begin(), entries.end(), e.name,
                         [](const Entry& a, const std::string& n) { return a.name < n; }) -
        entries.begin());
    for (const std::string& tail : momenta::ShortNames(e.name)) {
      by_tail[tail].emplace_back(index, name_at[index] + e.name.size() - tail.size());
    }
  }
  out << "static const EmbeddedShortName kEmbeddedLibraryShortNames[] = {\n";
  for (const auto& [tail, found] : by_tail) {
    for (const auto& [index, at] : found) out << "  {" << at << ", " << index << "},\n";
  }
  out << "};\n";
  // Written only when it changed, so that a rebuild does not recompile builtin_library.cc.
  return momenta::WriteIfChanged(argv[1], out.str()) ? 0 : 1;
}
