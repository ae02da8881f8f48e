#pragma once
/// A model or library file as one YAML document (core/lang/yaml_loader.h): its text, refused when
/// it is not a regular file (a directory, a FIFO, a device) or larger than a model can sensibly
/// be, and its single document, refused when the file is empty, holds a second document, nests
/// deeper than yaml-cpp reads or gives a key twice in one mapping (which YAML would read as the
/// first value only).

#include <memory>
#include <string>

#include "core/base/error.h"
#include "core/lang/yaml_tree.h"

namespace momenta {

/// The place of a 0-based line and column in `file` (a node's YamlMark, a yaml-cpp exception's
/// mark); the file alone when the line is negative (yaml-cpp's null mark).
SourceLoc MarkLoc(const std::string& file, int line, int column);
inline SourceLoc MarkLoc(const std::string& file, const YamlMark& mark) {
  return MarkLoc(file, mark.line, mark.column);
}

/// The text of the model or library file `path`; `what` names it in messages ("model file").
std::string ReadModelText(const std::string& path, const char* what);

/// The single YAML document of `text`, read from `file` (core/lang/yaml_document.h chooses the
/// reader). Throws ModelError at file:line:col for a syntax error, YAML nested too deeply, a
/// second document, an empty text and a key given twice; `what` names the file in messages.
std::unique_ptr<YamlDoc> ParseYamlFile(const std::string& text, const std::string& file,
                                       const std::string& what);

}  // namespace momenta
