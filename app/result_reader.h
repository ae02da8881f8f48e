#pragma once
/// Reads a result file momenta wrote (CSV, or the MAT v4 result layout of mat_writer.h) back as
/// columns, for `momenta report` and `momenta plot`.

#include <stdexcept>
#include <string>
#include <vector>

namespace momenta {

struct ResultTable {
  std::vector<std::string> names;  ///< the columns after time
  std::vector<double> time;
  std::vector<std::vector<double>> values;  ///< values[column][row]

  /// The index of column `name`; throws std::invalid_argument listing the valid names.
  size_t Column(const std::string& name) const;
};

/// Reads `path` (MAT when it ends in .mat, else CSV). Throws std::runtime_error naming the file
/// (and for a CSV the line) when it cannot be read or is not a result file: also at once when it
/// is not a regular file (a FIFO, a device), is larger than half the memory budget, or is a MAT
/// file whose matrix headers claim more values than the file holds (app/mat_header_check.h).
ResultTable ReadResult(const std::string& path);

}  // namespace momenta
