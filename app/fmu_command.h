#pragma once
/// `momenta fmu MODEL [-p NAME=VALUE]... [-o NAME.fmu] [--kind me|cs|both]`: the model as an FMI
/// 2.0 FMU (Model Exchange, Co-Simulation or both): modelDescription.xml from the built model
/// (fmu/fmu_layout.h), the FMU runtime (fmu/, self-contained) as binaries/linux64/<id>.so, and the
/// model file with its uses: files and the export's parameter values in resources/, from which
/// the runtime builds the model when it is instantiated.

#include <string>
#include <vector>

#include "fmu/fmu_layout.h"

namespace momenta {

struct FmuArgs {
  std::string model;
  std::vector<std::string> params;  ///< -p NAME=VALUE
  std::string out;                  ///< -o; empty: <model stem>.fmu
  std::string kind = "both";        ///< --kind: me, cs or both
};

int RunFmu(const FmuArgs& args);

/// The modelDescription.xml of `model` laid out as `layout`, for the kinds asked for.
std::string ModelDescriptionXml(const CompiledModel& model, const fmu::FmuLayout& layout,
                                const std::string& doc, bool model_exchange, bool co_simulation);

}  // namespace momenta
