// `momenta simulate -o FILE.mat`: the OpenModelica/Dymola MAT v4 result file, read back here with
// libmatio's reading side (Mat_Open/Mat_VarRead, nothing of momenta's writer), decoded through
// dataInfo as a Modelica result reader does, and compared value by value with the CSV of the same
// run.

#include <gtest/gtest.h>
#include <matio.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "tests/app/cli_support.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::Lines;
using testing::TempDir;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

struct VarFree {
  void operator()(matvar_t* v) const { Mat_VarFree(v); }
};
using Var = std::unique_ptr<matvar_t, VarFree>;

/// A MAT file's matrices as a reader sees them.
struct MatFile {
  std::map<std::string, Var> vars;
  std::vector<std::string> order;  ///< the matrices in file order

  explicit MatFile(const std::string& path) {
    mat_t* mat = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
    if (!mat) return;
    EXPECT_EQ(Mat_GetVersion(mat), MAT_FT_MAT4);
    while (matvar_t* info = Mat_VarReadNextInfo(mat)) {
      order.push_back(info->name);
      Mat_VarFree(info);
    }
    for (const auto& name : order) vars[name] = Var(Mat_VarRead(mat, name.c_str()));
    Mat_Close(mat);
  }
  const matvar_t* operator[](const std::string& name) const {
    auto it = vars.find(name);
    return it == vars.end() ? nullptr : it->second.get();
  }
};

size_t Rows(const matvar_t* v) { return v->dims[0]; }
size_t Cols(const matvar_t* v) { return v->dims[1]; }

/// The texts of a char matrix, one per column (binTrans) or per row (binNormal), without the
/// padding (NUL or blank).
std::vector<std::string> Texts(const matvar_t* v, bool per_column) {
  std::vector<std::string> out;
  const size_t rows = Rows(v), cols = Cols(v);
  EXPECT_EQ(v->class_type, MAT_C_CHAR);
  EXPECT_EQ(v->data_size, 1) << "char data of " << v->name;
  const auto* bytes = static_cast<const unsigned char*>(v->data);
  for (size_t i = 0; i < (per_column ? cols : rows); ++i) {
    std::string s;
    for (size_t j = 0; j < (per_column ? rows : cols); ++j) {
      const unsigned char c = per_column ? bytes[i * rows + j] : bytes[j * rows + i];
      s += static_cast<char>(c);
    }
    while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
    out.push_back(s);
  }
  return out;
}

double At(const matvar_t* v, size_t r, size_t c) { return static_cast<const double*>(v->data)[c * Rows(v) + r]; }

/// The CSV written by `simulate -o x.csv`: header and numbers (exactly as parsed by strtod).
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};
Csv ReadCsv(const std::string& path) {
  Csv csv;
  std::vector<std::string> lines = Lines(testing::ReadText(path));
  if (lines.empty()) return csv;
  std::stringstream h(lines[0]);
  std::string cell;
  while (std::getline(h, cell, ',')) csv.header.push_back(cell);
  for (size_t k = 1; k < lines.size(); ++k) {
    std::vector<double> row;
    std::stringstream s(lines[k]);
    while (std::getline(s, cell, ',')) row.push_back(std::strtod(cell.c_str(), nullptr));
    csv.rows.push_back(row);
  }
  return csv;
}

/// Each matrix's name and MAT v4 type (MOPT: 0 double, 20 int32, 51 uint8 text) from the file's
/// own headers (little-endian, as on the machines momenta runs on).
std::vector<std::pair<std::string, int32_t>> MatV4Types(const std::string& path) {
  std::vector<std::pair<std::string, int32_t>> out;
  const std::string bytes = testing::ReadText(path);
  size_t at = 0;
  while (at + 20 <= bytes.size()) {
    int32_t h[5];
    std::memcpy(h, bytes.data() + at, sizeof h);
    const int32_t type = h[0], rows = h[1], cols = h[2], namelen = h[4];
    const size_t element = type % 100 / 10 == 0 ? 8 : type % 100 / 10 == 2 ? 4 : type % 100 / 10 == 5 ? 1 : 0;
    if (element == 0 || h[3] != 0 || namelen < 1) break;
    out.emplace_back(std::string(bytes.data() + at + 20, namelen - 1), type);
    at += 20 + namelen + static_cast<size_t>(rows) * cols * element;
  }
  EXPECT_EQ(at, bytes.size()) << "the headers do not account for the whole file";
  return out;
}

class MatTest : public ::testing::Test {
 protected:
  CliResult Momenta(const std::vector<std::string>& args) { return testing::RunMomenta(args, dir_.path()); }
  TempDir dir_;
};

TEST_F(MatTest, CarrierCollisionMatEqualsItsCsv) {
  const std::string model = testing::SourcePath("models/carrier_collision.yaml");
  // The same run twice, one -p included so that data_1 shows an overridden value.
  CliResult mat_run = Momenta({"simulate", model, "-p", "eS=0.4", "-o", "result.mat", "-q"});
  ASSERT_EQ(mat_run.exit_code, kExitOk) << mat_run.err;
  EXPECT_EQ(mat_run.out, "");
  CliResult csv_run = Momenta({"simulate", model, "-p", "eS=0.4", "-o", "result.csv", "-q"});
  ASSERT_EQ(csv_run.exit_code, kExitOk) << csv_run.err;
  const Csv csv = ReadCsv(dir_.File("result.csv"));
  ASSERT_GT(csv.rows.size(), 100u);
  ASSERT_EQ(csv.header.size(), 11u);  // time + 10 outputs

  MatFile f(dir_.File("result.mat"));
  // The six matrices, in OpenModelica's order.
  ASSERT_EQ(f.order, (std::vector<std::string>{"Aclass", "name", "description", "dataInfo", "data_1", "data_2"}));
  EXPECT_EQ(MatV4Types(dir_.File("result.mat")),
            (std::vector<std::pair<std::string, int32_t>>{
                {"Aclass", 51}, {"name", 51}, {"description", 51}, {"dataInfo", 20}, {"data_1", 0}, {"data_2", 0}}));
  // Aclass is stored as four rows of text.
  EXPECT_EQ(Texts(f["Aclass"], false), (std::vector<std::string>{"Atrajectory", "1.1", "", "binTrans"}));
  // binTrans: names are columns.
  const std::vector<std::string> names = Texts(f["name"], true);
  const std::vector<std::string> descriptions = Texts(f["description"], true);
  const matvar_t* info = f["dataInfo"];
  const matvar_t* data1 = f["data_1"];
  const matvar_t* data2 = f["data_2"];
  ASSERT_TRUE(info && data1 && data2);
  // libmatio reads every numeric MAT v4 matrix as doubles; the stored types are checked from the
  // headers themselves (MatV4Types).
  ASSERT_EQ(info->data_type, MAT_T_DOUBLE);
  ASSERT_EQ(data1->data_type, MAT_T_DOUBLE);
  ASSERT_EQ(data2->data_type, MAT_T_DOUBLE);
  ASSERT_EQ(Rows(info), 4u);
  ASSERT_EQ(Cols(info), names.size());
  ASSERT_EQ(descriptions.size(), names.size());
  ASSERT_EQ(names[0], "time");
  EXPECT_EQ(descriptions[0], "Simulation time [s]");
  // data_2: one column per output row, time in row 1.
  ASSERT_EQ(Cols(data2), csv.rows.size());
  ASSERT_EQ(Rows(data2), csv.header.size());
  ASSERT_EQ(Cols(data1), 2u);

  // Decode every variable through dataInfo, as a result reader does.
  std::vector<int32_t> di_values;
  for (size_t k = 0; k < 4 * names.size(); ++k) {
    const double d = static_cast<const double*>(info->data)[k];
    ASSERT_EQ(d, std::floor(d));
    di_values.push_back(static_cast<int32_t>(d));
  }
  const int32_t* di = di_values.data();
  auto value = [&](size_t var, size_t row) {
    const int32_t matrix = di[4 * var], index = di[4 * var + 1];
    const double sign = index < 0 ? -1.0 : 1.0;
    const size_t r = static_cast<size_t>(std::abs(index)) - 1;
    if (matrix == 1) return sign * At(data1, r, row == 0 ? 0 : 1);  // start / stop value
    return sign * At(data2, r, row);  // 0 (time) and 2 (trajectories) index data_2
  };
  EXPECT_EQ(di[0], 0);   // time: the abscissa
  EXPECT_EQ(di[1], 1);   // in row 1 of data_2
  EXPECT_EQ(di[2], 0);   // linear interpolation
  EXPECT_EQ(di[3], -1);  // not defined outside the time range
  std::map<std::string, size_t> by_name;
  for (size_t j = 0; j < names.size(); ++j) {
    by_name[names[j]] = j;
    EXPECT_TRUE(di[4 * j] == 0 || di[4 * j] == 1 || di[4 * j] == 2) << names[j];
    EXPECT_EQ(di[4 * j + 2], 0) << names[j];
  }
  // Every CSV column, every row: the same double.
  for (size_t c = 0; c < csv.header.size(); ++c) {
    ASSERT_TRUE(by_name.count(csv.header[c])) << csv.header[c] << " is not in the MAT file";
    const size_t var = by_name[csv.header[c]];
    EXPECT_EQ(di[4 * var], c == 0 ? 0 : 2) << csv.header[c];
    for (size_t k = 0; k < csv.rows.size(); ++k) {
      ASSERT_EQ(value(var, k), csv.rows[k][c]) << csv.header[c] << " at row " << k;
    }
  }
  // data_1: the time range in row 1, then the parameters, the same at start and stop.
  EXPECT_EQ(At(data1, 0, 0), csv.rows.front()[0]);
  EXPECT_EQ(At(data1, 0, 1), 0.5);  // the experiment's stop
  const std::map<std::string, double> expected = {{"mA", 40}, {"mB", 40}, {"mS", 15}, {"vA0", 5},
                                                  {"eC", 0.8}, {"eS", 0.4}, {"A.m", 40}, {"suitcase.e", 0.4}};
  for (const auto& [name, v] : expected) {
    ASSERT_TRUE(by_name.count(name)) << name << " is not in the MAT file";
    const size_t var = by_name[name];
    EXPECT_EQ(di[4 * var], 1) << name;
    EXPECT_EQ(value(var, 0), v) << name;
    EXPECT_EQ(value(var, 1), v) << name;
  }
  // A parameter's description is its doc and unit.
  EXPECT_EQ(descriptions[by_name["mA"]], "mass of carrier A [kg]");
  // An output's description is its unit, as OpenModelica writes it.
  EXPECT_EQ(descriptions[by_name["B.v"]], "[m/s]");
  // The closed form at the end: B after both impacts (eC = 0.8, eS = 0.4).
  const double vB1 = 40 * 5 * 1.8 / 80, vB2 = (40 - 0.4 * 15) * vB1 / 55;
  EXPECT_NEAR(value(by_name["B.v"], csv.rows.size() - 1), vB2, 1e-9);
}

TEST_F(MatTest, UnwritableMatFileExitsWithThree) {
  const std::string model = testing::SourcePath("models/carrier_collision.yaml");
  CliResult r = Momenta({"simulate", model, "-o", "no-such-dir/result.mat"});
  EXPECT_EQ(r.exit_code, kExitSolver) << r.out << r.err;
  EXPECT_TRUE(Contains(r.err, "momenta: cannot write the results file no-such-dir/result.mat: No such file or directory"))
      << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_FALSE(std::filesystem::exists(dir_.File("no-such-dir")));
}

TEST_F(MatTest, AFailedMatWriteExitsWithThreeNamingTheFile) {
  const std::string model = testing::SourcePath("models/carrier_collision.yaml");
  // A .mat name that is /dev/full (every write fails with ENOSPC), which libmatio would not notice.
  if (std::filesystem::exists("/dev/full")) {
    std::filesystem::create_symlink("/dev/full", dir_.File("full.mat"));
    CliResult r = Momenta({"simulate", model, "-o", "full.mat"});
    EXPECT_EQ(r.exit_code, kExitSolver) << r.out << r.err;
    EXPECT_TRUE(Contains(r.err, "momenta: cannot write the results file full.mat: No space left on device")) << r.err;
    EXPECT_FALSE(Contains(r.out, "simulated")) << "no success summary after a failed write:\n" << r.out;
  }
  // A full disk, as a file size limit of a few KiB makes one (the file is 13 KB; SIGXFSZ ignored so
  // that the write fails with EFBIG instead of killing the process).
  CliResult r = testing::RunMomentaWithDeadline({"simulate", model, "-o", "big.mat"}, dir_.path(), 60,
                                                {"/bin/sh", "-c", "trap '' XFSZ; ulimit -f 4; exec \"$0\" \"$@\""});
  EXPECT_EQ(r.exit_code, kExitSolver) << r.out << r.err;
  EXPECT_TRUE(Contains(r.err, "momenta: cannot write the results file big.mat: only ")) << r.err;
  EXPECT_TRUE(Contains(r.err, "(is the disk full?)")) << r.err;
}

TEST_F(MatTest, FailedRunKeepsItsRowsInTheMatFile) {
  // x' = x^2 from 1 blows up at t = 1: the rows before it are kept, as in the CSV.
  dir_.Write("blowup.yaml", R"(model: Blowup
define:
  Blow:
    variables:
      x: {start: 1, fixed: true}
    equations:
      - der(x) = x^2
components:
  b: {type: Blow}
experiment: {stop: 2, interval: 0.1}
outputs: [b.x]
)");
  CliResult r = Momenta({"simulate", "blowup.yaml", "-o", "blowup.mat"});
  EXPECT_EQ(r.exit_code, kExitSolver) << r.err;
  EXPECT_TRUE(Contains(r.err, "are kept in blowup.mat")) << r.err;
  MatFile f(dir_.File("blowup.mat"));
  const matvar_t* data2 = f["data_2"];
  ASSERT_TRUE(data2);
  ASSERT_EQ(Rows(data2), 2u);
  ASSERT_GE(Cols(data2), 10u);
  for (size_t k = 0; k < Cols(data2); ++k) {
    const double t = At(data2, 0, k);
    EXPECT_LT(t, 1);
    EXPECT_NEAR(At(data2, 1, k), 1 / (1 - t), 1e-3 / (1 - t));
  }
  // No parameters: data_1 holds the time range alone.
  ASSERT_TRUE(f["data_1"]);
  EXPECT_EQ(Rows(f["data_1"]), 1u);
}

}  // namespace
}  // namespace momenta
