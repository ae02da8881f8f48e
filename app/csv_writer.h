#pragma once
/// Writes simulation rows as CSV: a header `time,<output>,…`, then one row per output time, every
/// number in the shortest form that reads back to the same double. Rows are flushed as they come,
/// so a failed run keeps what it computed.

#include <cstdio>
#include <string>
#include <vector>

namespace momenta {

class CsvWriter {
 public:
  /// Opens `path` ("-" for standard output). Throws std::runtime_error when it cannot.
  CsvWriter(const std::string& path, const std::vector<std::string>& names);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  void Row(double t, const std::vector<double>& values);
  size_t rows() const { return rows_; }

 private:
  std::FILE* file_ = nullptr;
  bool owned_ = false;
  size_t rows_ = 0;
  std::string line_;
};

/// The shortest decimal text that reads back as `v`.
std::string FormatDouble(double v);

}  // namespace momenta
