#pragma once
/// The table of the MAT plugin (momenta-mat.so, app/mat_plugin.cc): the libmatio calls that write
/// and read MAT v4 files, behind plain C functions so that only the plugin links libmatio (and
/// through it HDF5, curl, OpenSSL…). momenta's side is app/mat_file.h.

#include <cstddef>

namespace momenta {

/// A matrix's element type, as momenta's result files use them.
enum MatElement : int {
  kMatOther = 0,   ///< any other class or storage type (read only)
  kMatChar = 1,    ///< char class, one byte an element
  kMatInt32 = 2,   ///< int32 class and storage
  kMatDouble = 3,  ///< double class and storage
};

/// A two-dimensional matrix, stored column by column.
struct MatMatrix {
  const char* name;
  int element;  ///< MatElement
  size_t rows, cols;
  const void* data;
};

struct MatPluginTable {
  int abi;  ///< kPluginAbi (app/plugin.h)
  /// Writes `count` matrices, in order, as a new MAT v4 file at `path` (uncompressed). 0 when every
  /// write and the close succeeded (libmatio does not notice every failed write: check the size);
  /// 1 when one failed; 2 when the file cannot be created, with errno in `*error`.
  int (*write_v4)(const char* path, const MatMatrix* matrices, size_t count, int* error);
  /// Opens a MAT file for reading; nullptr when it is not one, or not readable.
  void* (*open)(const char* path);
  /// Reads matrix `name` of an open file into `*out` (its data stays valid until free_matrix);
  /// returns the matrix's handle, nullptr when the file has no such (two-dimensional) matrix.
  void* (*read)(void* file, const char* name, MatMatrix* out);
  void (*free_matrix)(void* matrix);
  void (*close)(void* file);
};

}  // namespace momenta

/// The plugin's one exported function: its momenta::MatPluginTable. The type is the one the loader
/// calls it through (app/plugin.h: a function called through a pointer of another type is
/// undefined behaviour, which UBSan's function check reports).
extern "C" const void* momenta_mat_plugin();
