#pragma once
/// The table of the zip plugin (momenta-zip.so, app/zip_plugin.cc): libzip, which `momenta fmu`
/// packs an FMU with, behind one plain C function, so that only the plugin links libzip (and
/// through it libcrypto, zlib and bzip2) and every other run starts without them (app/plugin.h).

#include <cstddef>

namespace momenta {

/// One file of an archive: `size` bytes at `data`, or, when `path` is not null, the file there.
struct ZipEntry {
  const char* name;
  const char* data;
  size_t size;
  const char* path;
};

struct ZipPluginTable {
  int abi;  ///< kPluginAbi (app/plugin.h)
  /// Writes `count` entries as a new zip archive at `path` (replacing one there). 0 on success;
  /// otherwise 1, with libzip's reason in `why` (at most `why_size` bytes, terminated).
  int (*write)(const char* path, const ZipEntry* entries, size_t count, char* why, size_t why_size);
};

}  // namespace momenta
