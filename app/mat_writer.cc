#include "app/mat_writer.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>

#include "app/mat_file.h"

namespace momenta {

namespace {

/// A char matrix whose columns are `texts`, NUL-padded to the longest text + 1 (OpenModelica's
/// convention; Dymola pads with spaces).
std::vector<char> Columns(const std::vector<std::string>& texts, size_t* height) {
  size_t h = 1;
  for (const auto& t : texts) h = std::max(h, t.size() + 1);
  std::vector<char> m(h * texts.size(), '\0');
  for (size_t j = 0; j < texts.size(); ++j) std::memcpy(m.data() + j * h, texts[j].data(), texts[j].size());
  *height = h;
  return m;
}

}  // namespace

bool IsMatPath(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".mat";
}

MatWriter::MatWriter(const std::string& path, const std::vector<std::string>& output_names,
                     std::vector<MatParameter> parameters, double start, double stop,
                     std::vector<std::string> output_units)
    : path_(path),
      outputs_(output_names),
      output_units_(std::move(output_units)),
      parameters_(std::move(parameters)),
      start_(start),
      stop_(stop) {
  if (std::string why; !HaveMat(&why)) {
    throw ResultWriteError("cannot write the results file " + path + ": MAT files need libmatio, but " + why);
  }
  errno = 0;
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) {
    throw ResultWriteError("cannot write the results file " + path + ": " + std::strerror(errno ? errno : EIO));
  }
}

MatWriter::~MatWriter() {
  if (file_) std::fclose(file_);
}

void MatWriter::Row(double t, const std::vector<double>& values) {
  data_.push_back(t);
  data_.insert(data_.end(), values.begin(), values.end());
  ++rows_;
}

/// The six matrices of a Dymola-compatible result file (MAT v4), ready to write.
struct MatWriter::Matrices {
  std::vector<char> aclass;  ///< four rows of 11 characters, stored column by column
  std::vector<char> name, description;
  size_t name_height = 0, description_height = 0, num_columns = 0;
  std::vector<int32_t> info;  ///< dataInfo: 4 rows per name
  std::vector<double> data1;  ///< the time range and each parameter at start and stop
};

MatWriter::Matrices MatWriter::MakeMatrices() const {
  const size_t n_out = outputs_.size(), n_par = parameters_.size();
  Matrices m;
  m.num_columns = 1 + n_out + n_par;
  std::vector<std::string> names, descriptions;
  names.reserve(m.num_columns);
  descriptions.reserve(m.num_columns);
  names.push_back("time");
  descriptions.push_back("Simulation time [s]");
  for (size_t k = 0; k < outputs_.size(); ++k) {
    names.push_back(outputs_[k]);
    const bool unit = k < output_units_.size() && !output_units_[k].empty();
    descriptions.push_back(unit ? "[" + output_units_[k] + "]" : "");
  }
  for (const auto& p : parameters_) {
    names.push_back(p.name);
    descriptions.push_back(p.description);
  }
  const char* aclass_rows[4] = {"Atrajectory", "1.1", "", "binTrans"};
  m.aclass.assign(4 * 11, '\0');
  for (size_t r = 0; r < 4; ++r) {
    for (size_t c = 0; c < std::strlen(aclass_rows[r]); ++c) m.aclass[c * 4 + r] = aclass_rows[r][c];
  }
  m.name = Columns(names, &m.name_height);
  m.description = Columns(descriptions, &m.description_height);
  m.info.resize(4 * m.num_columns);
  auto set_info = [&](size_t j, int32_t matrix, int32_t index, int32_t extrapolation) {
    m.info[4 * j] = matrix;
    m.info[4 * j + 1] = index;
    m.info[4 * j + 2] = 0;  // linear interpolation
    m.info[4 * j + 3] = extrapolation;
  };
  set_info(0, 0, 1, -1);  // time: the abscissa, row 1 of data_2, not defined outside the range
  for (size_t k = 0; k < n_out; ++k) set_info(1 + k, 2, static_cast<int32_t>(k + 2), 0);
  for (size_t p = 0; p < n_par; ++p) set_info(1 + n_out + p, 1, static_cast<int32_t>(p + 2), 0);
  // data_1: the time range, then each parameter, at the start (column 1) and stop (column 2).
  const size_t n1 = 1 + n_par;
  m.data1.resize(2 * n1);
  m.data1[0] = start_;
  m.data1[n1] = stop_;
  for (size_t p = 0; p < n_par; ++p) m.data1[1 + p] = m.data1[n1 + 1 + p] = parameters_[p].value;
  return m;
}

void MatWriter::WriteTemporary(const std::string& temp, Matrices* m) {
  const size_t n = m->num_columns;
  const std::vector<MatMatrix> matrices = {
      {"Aclass", kMatChar, 4, 11, m->aclass.data()},
      {"name", kMatChar, m->name_height, n, m->name.data()},
      {"description", kMatChar, m->description_height, n, m->description.data()},
      {"dataInfo", kMatInt32, 4, n, m->info.data()},
      {"data_1", kMatDouble, 1 + parameters_.size(), 2, m->data1.data()},
      {"data_2", kMatDouble, 1 + outputs_.size(), rows_, data_.data()},
  };
  uintmax_t expected_bytes = 0;  // MAT v4: per matrix a 20-byte header, the name with its NUL, the data
  for (const MatMatrix& matrix : matrices) {
    const size_t element = matrix.element == kMatDouble ? 8 : matrix.element == kMatInt32 ? 4 : 1;
    expected_bytes += 20 + std::strlen(matrix.name) + 1 + matrix.rows * matrix.cols * element;
  }
  int error = 0;
  const int written = WriteMat4(temp, matrices, &error);
  if (written == 2) Fail("cannot create the temporary file " + temp, error);
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(temp, ec);
  if (written != 0 || ec || size != expected_bytes) {
    Fail("only " + std::to_string(ec ? 0 : size) + " of " + std::to_string(expected_bytes) +
             " bytes were written to the temporary file " + temp + " (is the disk full?)",
         0);
  }
}

void MatWriter::CopyToResults(const std::string& temp) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(temp.c_str(), "rb"), &std::fclose);
  if (!in) Fail("cannot read back the temporary file " + temp, errno);
  std::vector<char> chunk(1 << 16);
  std::FILE* out = file_;
  file_ = nullptr;
  errno = 0;
  bool copied = true;
  size_t got = 0;
  while (copied && (got = std::fread(chunk.data(), 1, chunk.size(), in.get())) > 0) {
    copied = std::fwrite(chunk.data(), 1, got, out) == got;
  }
  copied = copied && !std::ferror(in.get()) && std::fflush(out) == 0;
  const int copy_errno = errno;
  if (std::fclose(out) != 0 && copied) {
    Fail("", errno);
  }
  if (!copied) Fail("", copy_errno);
}

void MatWriter::Close() {
  if (!file_) return;
  Matrices matrices = MakeMatrices();
  // libmatio 1.5 does not report failed writes (a full disk, /dev/full): it writes a temporary
  // regular file, whose size is checked, and that file's bytes are copied to the results file
  // with every write checked.
  std::string temp = (std::filesystem::temp_directory_path() / "momenta-XXXXXX.mat").string();
  const int fd = mkstemps(temp.data(), 4);
  if (fd < 0) Fail("cannot create a temporary file in " + std::filesystem::temp_directory_path().string(), errno);
  close(fd);
  struct TempRemover {
    std::string path;
    ~TempRemover() { std::remove(path.c_str()); }
  } remover{temp};
  WriteTemporary(temp, &matrices);
  CopyToResults(temp);
}

void MatWriter::Fail(const std::string& what, int error) const {
  std::string text = "cannot write the results file " + path_ + ": ";
  if (!what.empty()) text += what + (error ? ": " : "");
  if (error || what.empty()) text += std::strerror(error ? error : EIO);
  throw ResultWriteError(text);
}

}  // namespace momenta
