#pragma once
/// momenta's plugins: shared objects that hold the code of a feature whose libraries are costly to
/// load and that most runs do not use (MPI with hwloc and libevent; libmatio with HDF5, curl,
/// OpenSSL…). The `momenta` binary links none of those libraries; it dlopen()s a plugin the first
/// time a run needs it (app/sweep_cluster.h under mpirun, app/mat_file.h for a .mat file), so a
/// run that writes a CSV file loads only what it uses.
///
/// A plugin is looked for in the directory of the running binary, then in <that directory>/../lib/
/// momenta: an installed prefix has bin/momenta and lib/momenta/, and the build tree puts the
/// plugins in build/lib/momenta/, found from build/app/momenta and build/tests/momenta_tests
/// alike. Each plugin exports one C function that returns its table of functions; the table
/// starts with kPluginAbi, so that a plugin from another build is refused rather than called.

#include <string>

namespace momenta {

/// The version of the plugins' tables (app/mpi_plugin.h, app/mat_plugin.h); bumped when one changes.
constexpr int kPluginAbi = 1;

/// The table that plugin `file` (e.g. "momenta-mat.so") returns from its function `symbol`, loaded
/// on first use and kept for the life of the process; nullptr when it cannot be, with the reason in
/// `*why` (not found in any of the directories, named; or dlopen's message; or a table of another
/// ABI). `global`: the plugin's symbols (and its libraries') are visible to what it loads later
/// (OpenMPI loads its own components with dlopen).
const void* LoadPlugin(const std::string& file, const char* symbol, bool global, std::string* why);

/// Where plugin `file` was found (or would be loaded from), "" when it is in none of the directories.
std::string FindPlugin(const std::string& file);

}  // namespace momenta
