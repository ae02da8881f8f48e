#pragma once
/// Writes simulation rows as CSV: a header `time,<output>,…`, then one row per output time, every
/// number in the shortest form that reads back to the same double. Complete rows are collected in
/// the writer's own buffer and written whole, at least every quarter second, so the file never
/// ends in the middle of a row, and a failed or interrupted run keeps what it computed. Every
/// write is checked: a full disk is an error, not a short file.

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace momenta {

/// The results file could not be written (a full disk, /dev/full, a closed pipe), whatever its
/// format.
class ResultWriteError : public std::runtime_error {
 public:
  explicit ResultWriteError(const std::string& message) : std::runtime_error(message) {}
};
using CsvWriteError = ResultWriteError;

/// Where `simulate` puts its rows: a CSV file (CsvWriter) or a MAT v4 result file (MatWriter).
class ResultWriter {
 public:
  virtual ~ResultWriter() = default;
  /// Adds one row: time and the outputs; throws ResultWriteError when a write fails.
  virtual void Row(double t, const std::vector<double>& values) = 0;
  /// Writes everything and closes the file; throws ResultWriteError when that fails.
  virtual void Close() = 0;
  /// Rows given to Row().
  virtual size_t rows() const = 0;
};

class CsvWriter : public ResultWriter {
 public:
  /// Opens `path` ("-" for standard output) and writes the header. Throws CsvWriteError naming the
  /// file when it cannot open it or write to it.
  CsvWriter(const std::string& path, const std::vector<std::string>& names);
  /// Writes what is left (errors are not reported here: call Close()).
  ~CsvWriter() override;
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  /// Adds one row; throws CsvWriteError when a write fails.
  void Row(double t, const std::vector<double>& values) override;
  /// Writes every row and closes the file; throws CsvWriteError when that fails.
  void Close() override;
  /// Rows given to Row().
  size_t rows() const override { return rows_; }

 private:
  void Flush();

  std::string path_;
  std::FILE* file_ = nullptr;
  bool owned_ = false;
  size_t rows_ = 0;
  std::string buffer_;  ///< complete lines not yet written
  std::chrono::steady_clock::time_point last_write_;
};

/// The shortest decimal text that reads back as `v`.
std::string FormatDouble(double v);

/// The header line `time,<name>,…` (with its line end) that CsvWriter writes.
std::string CsvHeader(const std::vector<std::string>& names);

/// Appends one row `t,<value>,…` (with its line end) as CsvWriter writes it.
void AppendCsvRow(double t, const std::vector<double>& values, std::string* out);

/// `text` as one CSV field: as it is, or in double quotes (quotes doubled) when it holds a comma,
/// a quote or a line end.
std::string CsvField(const std::string& text);

}  // namespace momenta
