#pragma once
/// What `momenta fmu` puts beside the model in the FMU's resources/ folder for the runtime:
/// resources/momenta-fmu.txt names the model file and the parameter values the FMU was exported
/// with (-p, in the parameters' units), one a line:
///     model carrier_collision.yaml
///     parameter eC 0.5

#include <string>

#include "core/build.h"

namespace momenta::fmu {

constexpr const char* kManifestName = "momenta-fmu.txt";

struct ResourceManifest {
  std::string model_file;  ///< relative to resources/
  ParameterOverrides overrides;
};

/// The manifest's text.
std::string ManifestText(const ResourceManifest& manifest);
/// Reads `resources`/momenta-fmu.txt; throws std::runtime_error naming the file when it is missing
/// or wrong.
ResourceManifest ReadManifest(const std::string& resources);

/// The path of a file:// URI (fmuResourceLocation), percent-escapes decoded; throws
/// std::runtime_error for another scheme.
std::string PathOfUri(const std::string& uri);

}  // namespace momenta::fmu
