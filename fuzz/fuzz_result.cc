// libFuzzer target: any bytes as a result file, read as `momenta report` and `momenta plot` read
// one (app/result_reader.h), and a column looked up by its name as `plot -y` does. Bytes that
// start like a MAT v4 header (a first int32 below 65 536, little- or big-endian) are written to a
// .mat file, anything else to a .csv file, so that the seeds of either kind are read as what
// they are. A std::runtime_error or std::invalid_argument naming the file is the normal answer
// to a damaged result; a crash, a sanitizer report, another exception (std::bad_alloc: a size
// believed from the file), a timeout or running out of memory is a finding.
//
// The file is written to $TMPDIR (or /tmp) under a name of this process's, and removed at exit.
// Result files are refused above half the memory budget, which the target sets to 64 MiB.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

#include "app/result_reader.h"

namespace {

std::string g_csv, g_mat;

void RemoveFiles() {
  std::remove(g_csv.c_str());
  std::remove(g_mat.c_str());
}

bool LooksLikeMat(const uint8_t* data, size_t size) {
  if (size < 20) return false;
  return (data[2] == 0 && data[3] == 0) || (data[0] == 0 && data[1] == 0);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  setenv("MOMENTA_MEMORY_MB", "64", /*overwrite=*/0);
  const char* tmp = std::getenv("TMPDIR");
  const std::string stem = std::string(tmp && *tmp ? tmp : "/tmp") + "/momenta-fuzz-result-" +
                           std::to_string(getpid());
  g_csv = stem + ".csv";
  g_mat = stem + ".mat";
  std::atexit(RemoveFiles);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace momenta;
  const std::string& path = LooksLikeMat(data, size) ? g_mat : g_csv;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const ResultTable r = ReadResult(path);
    // Every column as long as the time, and a name found where it is (as plot -y looks it up).
    if (r.values.size() != r.names.size()) __builtin_trap();
    for (const auto& column : r.values) {
      if (column.size() != r.time.size()) __builtin_trap();
    }
    if (!r.names.empty() && r.names[r.Column(r.names.back())] != r.names.back()) __builtin_trap();
  } catch (const std::runtime_error&) {
    // A damaged or foreign file, said so: the expected outcome for most inputs.
  }
  return 0;
}
