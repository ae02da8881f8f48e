#include "app/result_reader.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>

#include "app/mat_file.h"
#include "app/mat_header_check.h"
#include "app/mat_writer.h"
#include "core/base/memory_budget.h"
#include "core/base/messages.h"
#include "core/base/regular_file.h"

namespace momenta {

namespace {

/// The fields of one CSV line (RFC 4180 quoting, as CsvField writes it).
std::vector<std::string> CsvFields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        out.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        out.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else if (c != '\r') {
      out.back() += c;
    }
  }
  return out;
}

ResultTable ReadCsv(const std::string& path, const RegularFile& file) {
  std::istringstream in(file.ReadAll());
  ResultTable r;
  std::string line;
  if (!std::getline(in, line))
    throw std::runtime_error(path + ": empty file; a result starts with the header time,<outputs>");
  std::vector<std::string> header = CsvFields(line);
  if (header.empty() || header[0] != "time") {
    throw std::runtime_error(path + ":1: not a momenta result: the header starts with '" +
                             header[0] + "', not 'time'");
  }
  r.names.assign(header.begin() + 1, header.end());
  r.values.resize(r.names.size());
  for (size_t lineno = 2; std::getline(in, line); ++lineno) {
    if (line.empty()) continue;
    std::vector<std::string> cells = CsvFields(line);
    if (cells.size() != header.size()) {
      throw std::runtime_error(path + ":" + std::to_string(lineno) + ": " +
                               std::to_string(cells.size()) + " values where the header has " +
                               std::to_string(header.size()));
    }
    for (size_t k = 0; k < cells.size(); ++k) {
      char* end = nullptr;
      const double v = std::strtod(cells[k].c_str(), &end);
      if (cells[k].empty() || *end != '\0') {
        throw std::runtime_error(path + ":" + std::to_string(lineno) + ": '" + cells[k] +
                                 "' in column " + header[k] + " is not a number");
      }
      (k == 0 ? r.time : r.values[k - 1]).push_back(v);
    }
  }
  return r;
}

/// The "name" matrix's texts (binTrans: one per column, NUL- or blank-padded).
std::vector<std::string> MatNames(const MatFile::Matrix& v) {
  std::vector<std::string> out;
  const size_t rows = v.rows, cols = v.cols;
  const auto* bytes = static_cast<const unsigned char*>(v.data);
  for (size_t j = 0; j < cols; ++j) {
    std::string s;
    for (size_t i = 0; i < rows; ++i) s += static_cast<char>(bytes[j * rows + i]);
    while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
    out.push_back(s);
  }
  return out;
}

/// The variables stored in data_2 (dataInfo row 1 is 2, or time), in the file's order.
ResultTable ReadMat(const std::string& path, const RegularFile& file) {
  // libmatio allocates what a header claims: every header is checked against the file first.
  CheckMatHeaders(file.fd(), file.size(), path);
  MatFile mat(path);
  if (!mat.ok())
    throw std::runtime_error("cannot read the result " + path +
                             ": not a MAT file, or not readable");
  auto read = [&](const char* name) {
    std::unique_ptr<MatFile::Matrix> v = mat.Read(name);
    if (!v)
      throw std::runtime_error(path + ": no matrix '" + std::string(name) +
                               "'; not a result file (Aclass, name, dataInfo, data_2)");
    return v;
  };
  auto names = read("name"), info = read("dataInfo"), data = read("data_2");
  // libmatio reads a MAT v4 file's numeric matrices as doubles (dataInfo is stored as int32).
  const bool info_ok = info->element == kMatInt32 || info->element == kMatDouble;
  if (names->element != kMatChar || !info_ok || data->element != kMatDouble || info->rows != 4 ||
      info->cols != names->cols) {
    throw std::runtime_error(path +
                             ": name, dataInfo and data_2 do not have the binTrans result layout");
  }
  const std::vector<std::string> all = MatNames(*names);
  std::vector<int32_t> di(4 * all.size());
  for (size_t k = 0; k < di.size(); ++k) {
    if (info->element == kMatInt32) {
      di[k] = static_cast<const int32_t*>(info->data)[k];
      continue;
    }
    // A value no int32 holds (a damaged file) is refused before it is converted.
    const double v = static_cast<const double*>(info->data)[k];
    if (!(std::fabs(v) <= 2147483647.0)) {
      throw std::runtime_error(path + ": dataInfo holds " + std::to_string(v) + ", not an index");
    }
    di[k] = static_cast<int32_t>(v);
  }
  const auto* d = static_cast<const double*>(data->data);
  const size_t per_row = data->rows, rows = data->cols;
  ResultTable r;
  for (size_t j = 0; j < all.size(); ++j) {
    const int32_t matrix = di[4 * j], index = di[4 * j + 1];
    const bool time = j == 0;
    if (!time && matrix != 2) continue;
    const size_t row = static_cast<size_t>(std::abs(index)) - 1;
    if (index == 0 || row >= per_row)
      throw std::runtime_error(path + ": dataInfo of " + all[j] + " points outside data_2");
    std::vector<double> col(rows);
    for (size_t k = 0; k < rows; ++k) col[k] = (index < 0 ? -1 : 1) * d[k * per_row + row];
    if (time) {
      r.time = std::move(col);
    } else {
      r.names.push_back(all[j]);
      r.values.push_back(std::move(col));
    }
  }
  return r;
}

}  // namespace

size_t ResultTable::Column(const std::string& name) const {
  for (size_t k = 0; k < names.size(); ++k) {
    if (names[k] == name) return k;
  }
  auto close = ClosestNames(name, names);
  throw std::invalid_argument("the result has no column '" + name + "'" +
                              (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                              " (valid: " + JoinNames(names, 60) + ")");
}

ResultTable ReadResult(const std::string& path) {
  // A result is read whole, into about as much memory again as its file: larger than half the
  // memory budget, it could not be read (and a FIFO or a device could not be read at all).
  const MemoryBudget budget = BuildMemoryBudget();
  std::unique_ptr<RegularFile> file;
  try {
    file = std::make_unique<RegularFile>(
        path, "result file", static_cast<uint64_t>(budget.bytes / 2),
        ", half the memory budget (" + budget.source + "); report and plot read a result whole");
  } catch (const FileRefused& e) {
    throw std::runtime_error(std::string("cannot read the result ") + e.what());
  }
  return IsMatPath(path) ? ReadMat(path, *file) : ReadCsv(path, *file);
}

}  // namespace momenta
