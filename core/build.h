#pragma once
/// The pipeline from a model file's spec to a CompiledModel: flatten, eliminate aliases, reduce
/// the index, analyse, prune, causalise, set up initialisation, compile. Each pass reports its
/// size and time (core/build_report.h, what `momenta check` prints).

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "core/build_report.h"
#include "core/compile/compiled_model.h"
#include "core/lang/model_spec.h"
#include "core/lang/units.h"

namespace momenta {

struct FlatSystem;

/// -p values written with a unit (`-p k=10kN/m`), by parameter name.
using OverrideUnits = std::map<std::string, Quantity>;

/// What a build takes besides the model's spec and the library.
struct BuildOptions {
  BuildOptions() = default;
  /// -p values alone, what most builds are given (implicit, so that they can be passed as such).
  // NOLINTNEXTLINE(runtime/explicit)
  BuildOptions(ParameterOverrides values) : overrides(std::move(values)) {}

  /// -p values by parameter name; those also in `override_units` are given in SI.
  ParameterOverrides overrides;
  /// -p values given with a unit: converted to their parameters' declared units, which the
  /// flattened model tells (BuildReport::overrides holds the values built with). Throws
  /// UsageError naming both units when the dimensions differ, or when the parameter declares no
  /// unit.
  OverrideUnits override_units;
  /// Outputs to add once the model is flattened (the report's scene, app/report_scene.h): called
  /// with the flattened model and the spec, to which it may append outputs. They come after the
  /// model's own outputs, which for a model that lists none are its states. The model is then
  /// flattened again with them.
  std::function<void(const FlatSystem& flat, ModelSpec* spec)> add_outputs;
  /// Hold the model's signal inputs that are connected to nothing (FlatSystem::free_inputs) as
  /// inputs of a linearisation, instead of refusing them: each input u becomes a state with
  /// der(u) = 0 and the initial equation u = its value in `input_values` (0 when not there), so
  /// the DAE's Jacobian holds the inputs' columns (solver/linearization.h). BuildReport::inputs
  /// names them. Only Real inputs can be held; a name in `input_values` that is not a free input
  /// throws UsageError listing those that are.
  bool hold_free_inputs = false;
  std::map<std::string, double> input_values;
};

/// Flattens, simplifies and compiles the model (the passes recorded in `report`). Throws
/// ModelError naming the file, line and the user's component.
std::shared_ptr<const CompiledModel> BuildModel(const ModelSpec& spec, const Library& library,
                                                const BuildOptions& options, BuildReport* report);
/// The same, releasing the spec once it is flattened: a large model's parsed file is about a
/// fifth of the build's peak memory, and nothing after flattening reads it.
std::shared_ptr<const CompiledModel> BuildModel(ModelSpec&& spec, const Library& library,
                                                const BuildOptions& options, BuildReport* report);

}  // namespace momenta
