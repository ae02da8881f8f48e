#include "app/mat_file.h"

#include <stdexcept>

#include "app/plugin.h"

namespace momenta {

namespace {

const MatPluginTable* Mat(std::string* why) {
  return static_cast<const MatPluginTable*>(LoadPlugin("momenta-mat.so", "momenta_mat_plugin", false, why));
}

/// The plugin's table, or std::runtime_error saying why there is none.
const MatPluginTable& MatOrThrow() {
  std::string why;
  const MatPluginTable* mat = Mat(&why);
  if (!mat) throw std::runtime_error("MAT files need libmatio, but " + why);
  return *mat;
}

}  // namespace

bool HaveMat(std::string* why) { return Mat(why) != nullptr; }

int WriteMat4(const std::string& path, const std::vector<MatMatrix>& matrices, int* error) {
  return MatOrThrow().write_v4(path.c_str(), matrices.data(), matrices.size(), error);
}

MatFile::MatFile(const std::string& path) : mat_(&MatOrThrow()), file_(mat_->open(path.c_str())) {}

MatFile::~MatFile() {
  if (file_) mat_->close(file_);
}

std::unique_ptr<MatFile::Matrix> MatFile::Read(const char* name) const {
  MatMatrix m{};
  void* handle = mat_->read(file_, name, &m);
  return handle ? std::make_unique<Matrix>(mat_, handle, m) : nullptr;
}

}  // namespace momenta
