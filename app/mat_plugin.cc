// The MAT plugin (app/mat_plugin.h): the only code of momenta that links libmatio.

#include "app/mat_plugin.h"

#include <matio.h>

#include <cerrno>
#include <memory>

#include "app/plugin.h"

namespace {

using momenta::MatMatrix;

/// Frees a matvar_t made with MAT_F_DONT_COPY_DATA (the data stays the caller's).
struct VarDeleter {
  void operator()(matvar_t* v) const { Mat_VarFree(v); }
};

int WriteV4(const char* path, const MatMatrix* matrices, size_t count, int* error) {
  errno = 0;
  mat_t* mat = Mat_CreateVer(path, nullptr, MAT_FT_MAT4);
  if (!mat) {
    *error = errno;
    return 2;
  }
  bool ok = true;
  for (size_t k = 0; k < count && ok; ++k) {
    const MatMatrix& m = matrices[k];
    matio_classes cls = MAT_C_CHAR;
    matio_types type = MAT_T_UINT8;
    if (m.element == momenta::kMatInt32) {
      cls = MAT_C_INT32;
      type = MAT_T_INT32;
    } else if (m.element == momenta::kMatDouble) {
      cls = MAT_C_DOUBLE;
      type = MAT_T_DOUBLE;
    }
    size_t dims[2] = {m.rows, m.cols};
    std::unique_ptr<matvar_t, VarDeleter> v(
        Mat_VarCreate(m.name, cls, type, 2, dims, const_cast<void*>(m.data), MAT_F_DONT_COPY_DATA));
    ok = v && Mat_VarWrite(mat, v.get(), MAT_COMPRESSION_NONE) == 0;
  }
  const bool closed = Mat_Close(mat) == 0;
  return ok && closed ? 0 : 1;
}

void* Open(const char* path) { return Mat_Open(path, MAT_ACC_RDONLY); }

/// libmatio's class and storage type as the element momenta's readers check.
int Element(const matvar_t* v) {
  if (v->class_type == MAT_C_CHAR && v->data_size == 1) return momenta::kMatChar;
  if (v->class_type == MAT_C_INT32 && v->data_type == MAT_T_INT32) return momenta::kMatInt32;
  if (v->class_type == MAT_C_DOUBLE && v->data_type == MAT_T_DOUBLE) return momenta::kMatDouble;
  return momenta::kMatOther;
}

void* Read(void* file, const char* name, MatMatrix* out) {
  matvar_t* v = Mat_VarRead(static_cast<mat_t*>(file), name);
  if (!v) return nullptr;
  if (v->rank != 2) {
    Mat_VarFree(v);
    return nullptr;
  }
  *out = MatMatrix{v->name, Element(v), v->dims[0], v->dims[1], v->data};
  return v;
}

void FreeMatrix(void* matrix) { Mat_VarFree(static_cast<matvar_t*>(matrix)); }

void Close(void* file) { Mat_Close(static_cast<mat_t*>(file)); }

constexpr momenta::MatPluginTable kTable = {momenta::kPluginAbi, WriteV4, Open, Read, FreeMatrix, Close};

}  // namespace

extern "C" __attribute__((visibility("default"))) const void* momenta_mat_plugin() {
  return &kTable;
}
