#pragma once
/// MAT files through libmatio, loaded from the MAT plugin (momenta-mat.so, app/mat_plugin.h) the
/// first time a run writes or reads one: a run that does not touch a .mat file never loads
/// libmatio, nor HDF5 and the libraries HDF5 brings.

#include <memory>
#include <string>
#include <vector>

#include "app/mat_plugin.h"

namespace momenta {

/// True when the MAT plugin loads; otherwise false with the reason in `*why` (when given).
bool HaveMat(std::string* why = nullptr);

/// Writes `matrices` as a new MAT v4 file (MatPluginTable::write_v4's result: 0, 1, or 2 with
/// `*error`). Throws std::runtime_error when the plugin cannot be loaded.
int WriteMat4(const std::string& path, const std::vector<MatMatrix>& matrices, int* error);

/// A MAT file open for reading.
class MatFile {
 public:
  /// Opens `path`; ok() is false when it is not a MAT file or not readable. Throws
  /// std::runtime_error when the plugin cannot be loaded.
  explicit MatFile(const std::string& path);
  ~MatFile();
  MatFile(const MatFile&) = delete;
  MatFile& operator=(const MatFile&) = delete;
  bool ok() const { return file_ != nullptr; }

  /// A matrix read from the file; its data is freed with it.
  class Matrix : public MatMatrix {
   public:
    Matrix(const MatPluginTable* mat, void* handle, const MatMatrix& matrix)
        : MatMatrix(matrix), mat_(mat), handle_(handle) {}
    ~Matrix() { mat_->free_matrix(handle_); }
    Matrix(const Matrix&) = delete;
    Matrix& operator=(const Matrix&) = delete;

   private:
    const MatPluginTable* mat_;
    void* handle_;
  };
  /// Matrix `name`, nullptr when the file has none.
  std::unique_ptr<Matrix> Read(const char* name) const;

 private:
  const MatPluginTable* mat_;
  void* file_ = nullptr;
};

}  // namespace momenta
