// libFuzzer target: any bytes as a model file, loaded and built with the builtin library (what
// `momenta check` does before printing). A ModelError is the normal answer to a bad model; a
// crash, a sanitizer report, another exception, a timeout or running out of memory is a finding.
//
// Sizes are checked against MOMENTA_MEMORY_MB (core/base/memory_budget.h); the target sets it to
// 64 MiB unless the environment gives another value, so that a `count:` the build would refuse
// on a small machine is refused here too and libFuzzer's -rss_limit_mb finds real leaks and
// blow-ups, not big but valid models.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/build.h"
#include "core/compile/model_state.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  setenv("MOMENTA_MEMORY_MB", "64", /*overwrite=*/0);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace momenta;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    ModelSpec spec = LoadModelString(text, "fuzz.yaml");
    BuildReport report;
    std::shared_ptr<const CompiledModel> model = BuildModel(spec, BuiltinLibrary(), {}, &report);
    ModelState state(model);
    state.SetParameters({});
  } catch (const ModelError&) {
    // The model is wrong and says so: the expected outcome for most inputs.
  }
  return 0;
}
