#include "app/csv_writer.h"

#include <charconv>
#include <stdexcept>

namespace momenta {

std::string FormatDouble(double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& names) {
  if (path == "-") {
    file_ = stdout;
  } else {
    file_ = std::fopen(path.c_str(), "w");
    owned_ = true;
    if (!file_) throw std::runtime_error("cannot write the results file " + path);
  }
  std::string header = "time";
  for (const auto& n : names) {
    // A name with a comma or quote is quoted, as CSV requires.
    if (n.find_first_of(",\"") != std::string::npos) {
      std::string q = "\"";
      for (char c : n) q += c == '"' ? std::string("\"\"") : std::string(1, c);
      header += "," + q + "\"";
    } else {
      header += "," + n;
    }
  }
  std::fprintf(file_, "%s\n", header.c_str());
}

CsvWriter::~CsvWriter() {
  if (owned_ && file_) std::fclose(file_);
}

void CsvWriter::Row(double t, const std::vector<double>& values) {
  line_.clear();
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, t);
  line_.append(buf, r.ptr);
  for (double v : values) {
    line_ += ',';
    r = std::to_chars(buf, buf + sizeof buf, v);
    line_.append(buf, r.ptr);
  }
  line_ += '\n';
  std::fwrite(line_.data(), 1, line_.size(), file_);
  ++rows_;
}

}  // namespace momenta
