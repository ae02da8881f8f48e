#pragma once
/// `momenta linearize MODEL [-p NAME=VALUE]... [--at T] [-u INPUT[=VALUE]]... [-y OUTPUT]...
/// [-o lin.json|lin.mat]`: the model's state-space form A, B, C, D at time T (after the
/// initialisation, or after a simulation to T), over the states the build chose, the model's
/// unconnected signal inputs and its outputs (solver/linearization.h computes it).

#include <optional>
#include <string>
#include <vector>

#include "solver/linearization.h"

namespace momenta {

struct LinearizeArgs {
  std::string model;
  std::vector<std::string> params;   ///< -p NAME=VALUE
  std::optional<double> at;          ///< --at: empty, the start time (after the initialisation)
  std::vector<std::string> inputs;   ///< -u NAME or NAME=VALUE (the operating value; default 0)
  std::vector<std::string> outputs;  ///< -y NAME, comma-separated lists gathered
  std::string out;                   ///< -o: .json or .mat; empty: JSON on standard output
};

int RunLinearize(const LinearizeArgs& args);

/// The JSON document `momenta linearize` writes: {"model", "time", "states", "inputs",
/// "outputs", "x0", "u0", "y0", "A", "B", "C", "D", "eigenvalues"}, the matrices as arrays of
/// rows, numbers with 17 significant digits, eigenvalues as [re, im] pairs.
std::string LinearizationJson(const std::string& model_name, const Linearization& lin);

/// Writes `lin` as a MAT v4 file in the layout of Dymola's dslin.mat, which
/// Modelica_LinearSystems2, DyMat and ModelicaRes read: `Aclass` (char rows "Alinear", "1.1",
/// "", "binNormal"), `nx` (1 x 1, the number of states), `ABCD` ((nx + ny) x (nx + nu), the
/// matrix [A B; C D]) and `xuyName` (char, one name a row: the states, the inputs, the outputs).
/// OpenModelica writes its linearisation as a Modelica or MATLAB text file, not a MAT file.
/// Throws std::runtime_error naming the file when it cannot be written.
void WriteLinearizationMat(const std::string& path, const Linearization& lin);

}  // namespace momenta
