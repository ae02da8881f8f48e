#pragma once
/// Writes simulation results as the MAT v4 result file that OpenModelica and Dymola write (their
/// "Atrajectory 1.1 binTrans" layout, read by OMEdit, Dymola, DyMat, BuildingsPy, ModelicaRes),
/// through libmatio. The file holds, in this order (stored dimensions, MAT v4 column-major):
///
///   Aclass       char 4 x 11: the rows "Atrajectory", "1.1", "", "binTrans"
///   name         char L x n: column j is variable j's name, NUL-padded (L = longest name + 1);
///                variable 1 is `time`, then the outputs, then the parameters
///   description  char D x n: the same for the descriptions ("Simulation time [s]", a parameter's
///                doc and [unit])
///   dataInfo     int32 4 x n: column j is [matrix, index, interpolation, extrapolation] of variable
///                j: time [0, 1, 0, -1]; output k [2, k + 1, 0, 0] (row k + 1 of data_2); parameter
///                p [1, p + 1, 0, 0] (row p + 1 of data_1). An index is 1-based (OpenModelica would
///                write a negated alias as a negative index; momenta writes none).
///   data_1       double (1 + parameters) x 2: column 1 the values at the start, column 2 at the
///                stop; row 1 is the time range [start, stop]
///   data_2       double (1 + outputs) x rows: column r is output row r, [t, outputs...]
///
/// "binTrans" says every matrix after Aclass is stored transposed (one column per variable or per
/// time point), which is what makes the file writable a row at a time; readers transpose it back.
/// The rows are kept in memory and the matrices are written by Close() (so a run that fails or
/// is interrupted still gets a complete file of the rows it computed). libmatio does not report
/// failed writes, so Close() has it write a temporary file, checks that file's size, and copies its
/// bytes to the results file with every write checked (a full disk or /dev/full is an error naming
/// the file, whether the results file is a regular file or not).

#include <cstdio>
#include <string>
#include <vector>

#include "app/csv_writer.h"

namespace momenta {

/// A parameter as data_1 stores it.
struct MatParameter {
  std::string name, description;
  double value = 0;
};

class MatWriter : public ResultWriter {
 public:
  /// Opens `path` at once (throws ResultWriteError naming it when it cannot be created).
  /// `output_units` (optional, one per output, "" when unknown) go into each output's
  /// description as OpenModelica writes them: "[m/s]".
  MatWriter(const std::string& path, const std::vector<std::string>& output_names,
            std::vector<MatParameter> parameters, double start, double stop,
            std::vector<std::string> output_units = {});
  ~MatWriter() override;
  MatWriter(const MatWriter&) = delete;
  MatWriter& operator=(const MatWriter&) = delete;

  void Row(double t, const std::vector<double>& values) override;
  /// Writes the six matrices and closes the file; throws ResultWriteError when that fails.
  void Close() override;
  size_t rows() const override { return rows_; }

 private:
  std::string path_;
  std::vector<std::string> outputs_, output_units_;
  std::vector<MatParameter> parameters_;
  /// Throws ResultWriteError "cannot write the results file <path>: <what>: <strerror(error)>".
  [[noreturn]] void Fail(const std::string& what, int error) const;
  struct Matrices;
  Matrices MakeMatrices() const;
  /// Writes the matrices and data_2 to `temp` and checks its size (libmatio reports no failed write).
  void WriteTemporary(const std::string& temp, Matrices* matrices);
  /// Copies `temp` into the results file, every write checked, and closes it.
  void CopyToResults(const std::string& temp);

  double start_, stop_;
  std::FILE* file_ = nullptr;  ///< the results file, open from construction to Close()
  std::vector<double> data_;  ///< data_2, column-major: 1 + outputs values per row
  size_t rows_ = 0;
};

/// True when `path` names a MAT file (ends in ".mat", any case).
bool IsMatPath(const std::string& path);

}  // namespace momenta
