// A model's own connectors, records and functions (`define:` and `uses:` files), laid over the
// library when the model is flattened (core/flatten/flatten.cc, ModelLibrary).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildError;
using testing::BuildYaml;
using testing::RunDefault;
using testing::Trajectory;

// A record and a record-valued function of the model's own: q = swap(p) negates a and swaps b's
// elements, exactly.
TEST(ModelLibraryTest, OwnRecordAndFunction) {
  const Trajectory t = RunDefault(BuildYaml(R"(
model: OwnRecord
define:
  Pair: {kind: record, fields: {a: {}, b: {shape: [2]}}}
  swap:
    kind: function
    inputs: {p: Pair}
    returns: Pair
    value: {a: -p.a, b: "[p.b[2], p.b[1]]"}
  Holder:
    variables: {p: {type: Pair}, q: {type: Pair}}
    equations:
      - p.a = time
      - p.b = [time, 2*time]
      - q = swap(p)
components:
  h: {type: Holder}
experiment: {stop: 1, interval: 0.25}
outputs: [h.q.a, "h.q.b[1]", "h.q.b[2]"]
)"));
  for (size_t r = 0; r < t.t.size(); ++r) {
    EXPECT_EQ(t.Column("h.q.a", r), -t.t[r]);
    EXPECT_EQ(t.Column("h.q.b[1]", r), 2 * t.t[r]);
    EXPECT_EQ(t.Column("h.q.b[2]", r), t.t[r]);
  }
}

// A connector type of the model's own (a thermal node: temperature and heat flow) and two
// components on it: a 2 J/K capacity that cools through a 0.5 W/K conductance to a fixed 300 K,
// from 400 K: T = 300 + 100 exp(-t/4) (rtol 1e-9 on 400 K: 1e-5 K allowed).
std::string Cooling(const std::string& uses) {
  return R"(
model: Cooling
)" + uses + R"(
define:
  Node: {kind: connector, potential: {T: {unit: K}}, flow: {Q: {unit: W}}}
  Capacity:
    parameters: {C: {value: 1}}
    connectors: {port: {type: Node}}
    variables: {T: {start: 400, fixed: true}}
    equations: [T = port.T, C*der(T) = port.Q]
  Conductance:
    parameters: {G: {value: 1}, T_ambient: {value: 300}}
    connectors: {port: {type: Node}}
    equations: [port.Q = G*(port.T - T_ambient)]
components:
  capacity: {type: Capacity, C: 2}
  conductance: {type: Conductance, G: 0.5}
connections: [[capacity.port, conductance.port]]
experiment: {stop: 8, tolerance: 1e-9}
outputs: [capacity.T]
)";
}

TEST(ModelLibraryTest, OwnConnector) {
  const Trajectory t = RunDefault(BuildYaml(Cooling("")));
  for (size_t r = 0; r < t.t.size(); ++r) {
    EXPECT_NEAR(t.Column("capacity.T", r), 300 + 100 * std::exp(-t.t[r] / 4), 1e-5) << "at t = " << t.t[r];
  }
}

// From a library file named in uses:, a record and a function serve the model's equations (the
// function called by its qualified name: the model is read before the files it uses).
TEST(ModelLibraryTest, RecordsAndFunctionsFromAUsesFile) {
  testing::TempDir dir;
  dir.Write("lib.yaml", R"(
Pair: {kind: record, fields: {a: {}, b: {}}}
Lib.total: {kind: function, inputs: {p: Pair}, value: p.a + p.b}
)");
  const std::string model = dir.Write("model.yaml", R"(
model: UsesRecord
uses: [lib.yaml]
define:
  Holder:
    variables: {p: {type: Pair}, s: {}}
    equations: [p.a = time, p.b = 2*time, s = Lib.total(p)]
components:
  h: {type: Holder}
experiment: {stop: 1, interval: 0.5}
outputs: [h.s]
)");
  const testing::CliResult r = testing::RunMomenta({"simulate", model, "-o", dir.File("out.csv")}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const testing::Csv csv = testing::ReadCsv(dir.File("out.csv"));
  ASSERT_FALSE(csv.rows.empty());
  EXPECT_EQ(csv.rows.back()[csv.Index("h.s")], 3.0);
}

// An unknown record in the model's own connector is an error at its declaration.
TEST(ModelLibraryTest, AnUnknownRecordInAnOwnConnectorIsNamed) {
  const std::string error = BuildError(R"(
model: Bad
define:
  Frame2: {kind: connector, potential: {R: {type: NoSuchRecord}}, flow: {f: {}}}
  Part:
    connectors: {frame: {type: Frame2}}
    equations: [frame.f = 0]
components:
  p: {type: Part}
)");
  EXPECT_NE(error.find("unknown type 'NoSuchRecord'"), std::string::npos) << error;
}

}  // namespace
}  // namespace momenta
