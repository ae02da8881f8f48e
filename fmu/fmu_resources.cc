// The FMU's resources manifest and its location (fmu_resources.h).

#include "fmu/fmu_resources.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace momenta::fmu {

std::string ManifestText(const ResourceManifest& manifest) {
  std::string text = "model " + manifest.model_file + "\n";
  for (const auto& [name, value] : manifest.overrides) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", value);
    text += "parameter " + name + " " + buf + "\n";
  }
  return text;
}

ResourceManifest ReadManifest(const std::string& resources) {
  const std::string path = resources + "/" + kManifestName;
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot read " + path + " (the FMU's resources are incomplete)");
  ResourceManifest manifest;
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    std::istringstream words(line);
    std::string key, name;
    words >> key;
    if (key == "model") {
      words >> manifest.model_file;
      continue;
    }
    double value = 0;
    if (key == "parameter" && (words >> name) && (words >> value)) {
      manifest.overrides[name] = value;
      continue;
    }
    if (!key.empty())
      throw std::runtime_error(path + ":" + std::to_string(line_number) + ": cannot read '" + line +
                               "'");
  }
  if (manifest.model_file.empty()) throw std::runtime_error(path + ": no 'model' line");
  return manifest;
}

std::string PathOfUri(const std::string& uri) {
  std::string rest;
  if (uri.rfind("file://", 0) == 0) {
    rest = uri.substr(7);
    if (rest.rfind("localhost/", 0) == 0) rest = rest.substr(9);
  } else if (uri.rfind("file:", 0) == 0) {
    rest = uri.substr(5);
  } else if (!uri.empty() && uri[0] == '/') {
    rest = uri;  // a plain path, as some importers pass
  } else {
    throw std::runtime_error("fmuResourceLocation '" + uri + "' is not a file:// URI");
  }
  std::string path;
  for (size_t k = 0; k < rest.size(); ++k) {
    if (rest[k] == '%' && k + 2 < rest.size()) {
      path += static_cast<char>(std::strtol(rest.substr(k + 1, 2).c_str(), nullptr, 16));
      k += 2;
    } else {
      path += rest[k];
    }
  }
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

}  // namespace momenta::fmu
