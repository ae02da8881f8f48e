#include "app/csv_writer.h"

#include <cerrno>
#include <charconv>
#include <cstring>

namespace momenta {

namespace {

/// Rows are written once this much has been collected, or this long after the last write.
constexpr size_t kBufferBytes = 1 << 16;
constexpr std::chrono::milliseconds kWriteEvery(250);

}  // namespace

std::string FormatDouble(double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string CsvHeader(const std::vector<std::string>& names) {
  std::string header = "time";
  // A name with a comma or quote is quoted, as CSV requires.
  for (const auto& n : names) {
    header += ',';
    header += CsvField(n);
  }
  return header + '\n';
}

void AppendCsvRow(double t, const std::vector<double>& values, std::string* out) {
  // Written in place: room for the longest form of every number (24 characters, "-2.2250738585072014e-308")
  // and its separator, then cut to what was written.
  constexpr size_t kLongest = 25;
  const size_t start = out->size();
  out->resize(start + (values.size() + 1) * kLongest);
  char* at = out->data() + start;
  char* const end = out->data() + out->size();
  at = std::to_chars(at, end, t).ptr;
  for (double v : values) {
    *at++ = ',';
    at = std::to_chars(at, end, v).ptr;
  }
  *at++ = '\n';
  out->resize(static_cast<size_t>(at - out->data()));
}

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& names) : path_(path) {
  if (path == "-") {
    file_ = stdout;
  } else {
    file_ = std::fopen(path.c_str(), "w");
    owned_ = true;
    if (!file_) throw ResultWriteError("cannot write the results file " + path + ": " + std::strerror(errno));
    // Unbuffered: each Flush() is one write of whole lines, not stdio's blocks.
    std::setvbuf(file_, nullptr, _IONBF, 0);
  }
  buffer_ = CsvHeader(names);
  // The header at once: a file that cannot be written is found before the run.
  Flush();
}

CsvWriter::~CsvWriter() {
  if (!file_) return;
  try {
    Flush();
  } catch (const CsvWriteError&) {
  }
  if (owned_) std::fclose(file_);
}

void CsvWriter::Row(double t, const std::vector<double>& values) {
  AppendCsvRow(t, values, &buffer_);
  ++rows_;
  if (buffer_.size() >= kBufferBytes || std::chrono::steady_clock::now() - last_write_ >= kWriteEvery) Flush();
}

void CsvWriter::Flush() {
  last_write_ = std::chrono::steady_clock::now();
  if (buffer_.empty()) return;
  // Whole lines in one write, pushed out of stdio's buffer at once.
  errno = 0;
  const bool ok = std::fwrite(buffer_.data(), 1, buffer_.size(), file_) == buffer_.size() && std::fflush(file_) == 0;
  buffer_.clear();
  if (!ok) {
    throw CsvWriteError("cannot write the results file " + (path_ == "-" ? std::string("(standard output)") : path_) +
                        ": " + std::strerror(errno ? errno : EIO));
  }
}

void CsvWriter::Close() {
  Flush();
  if (owned_) {
    std::FILE* f = file_;
    file_ = nullptr;
    if (std::fclose(f) != 0) throw CsvWriteError("cannot write the results file " + path_ + ": " + std::strerror(errno));
  } else {
    file_ = nullptr;
  }
}

}  // namespace momenta
