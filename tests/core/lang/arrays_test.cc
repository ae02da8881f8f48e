// Vectors and matrices (core/lang/arrays.h): declarations with shape: become scalar elements, array
// equations one equation per element, and array operations are evaluated on the syntax tree.
// Checked by closed forms (a projectile, a rotation), by hand values (cross, norm, sum, identity,
// zeros), by the names of outputs and -p, by element-by-element connections of vector signals
// and of a connector type with vector variables, and by the text of every error.

#include <gtest/gtest.h>

#include <cmath>

#include "core/lang/arrays.h"
#include "core/flatten/flat_system.h"
#include "core/lang/parser.h"
#include "tests/support/test_models.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

using testing::BuildError;
using testing::BuildYaml;
using testing::RunDefault;
using testing::Trajectory;

// A body in a plane: position r, velocity v, pushed by a vector signal F, falling in g.
const char* kProjectile = R"y(model: Projectile
parameters:
  g: [0, -9.81]
define:
  Body:
    parameters:
      m: 2
      gravity: {value: [0, -1], shape: [2]}
      r0: {value: [0, 0], shape: [2]}
      v0: {value: [3, 4], shape: [2]}
    connectors:
      F: {type: RealInput, shape: [2]}
    variables:
      r: {shape: [2], start: r0, fixed: true}
      v: {shape: [2], start: v0, fixed: true}
    equations:
      - der(r) = v
      - m*der(v) = F + m*gravity
  Push:
    parameters: {f: {value: [1, 0.5], shape: [2]}}
    connectors: {y: {type: RealOutput, shape: [2]}}
    equations:
      - y = f
components:
  body: {type: Body, gravity: g, r0: [0.5, 4]}
  push: {type: Push}
connections:
  - [push.y, body.F]
experiment: {stop: 2, interval: 0.25, tolerance: 1e-10}
outputs: [body.r, "body.v[2]", "norm(body.v)"]
)y";

TEST(ArraysTest, ProjectileMatchesTheClosedForm) {
  Trajectory tr = RunDefault(BuildYaml(kProjectile));
  // One CSV column per element, named as Modelica names them.
  ASSERT_EQ(tr.names, (std::vector<std::string>{"body.r[1]", "body.r[2]", "body.v[2]", "norm(body.v)"}));
  const double m = 2, fx = 1, fy = 0.5, g = 9.81;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    const double ax = fx / m, ay = fy / m - g;
    EXPECT_NEAR(tr.Column("body.r[1]", k), 0.5 + 3 * t + 0.5 * ax * t * t, 1e-9) << t;
    EXPECT_NEAR(tr.Column("body.r[2]", k), 4 + 4 * t + 0.5 * ay * t * t, 1e-9) << t;
    EXPECT_NEAR(tr.Column("body.v[2]", k), 4 + ay * t, 1e-9) << t;
    EXPECT_NEAR(tr.Column("norm(body.v)", k), std::hypot(3 + ax * t, 4 + ay * t), 1e-9) << t;
  }
}

TEST(ArraysTest, ElementParameterFromTheCommandLineAndWholeArrayStart) {
  testing::Built b = BuildYaml(kProjectile);
  Trajectory base = RunDefault(b);
  Trajectory moved = RunDefault(b, {{"body.r0[2]", 10}});
  const size_t last = base.t.size() - 1;
  EXPECT_NEAR(moved.Column("body.r[2]", last) - base.Column("body.r[2]", last), 6, 1e-9);
  EXPECT_NEAR(moved.Column("body.r[1]", last), base.Column("body.r[1]", last), 1e-12);
  // A model parameter's element too: no gravity in y.
  Trajectory floating = RunDefault(b, {{"g[2]", 0}});
  EXPECT_NEAR(floating.Column("body.v[2]", last), 4 + 0.25 * 2, 1e-9);
}

// A rotation matrix times a vector; transpose(R)*R is the identity; matrix elements by name.
TEST(ArraysTest, RotationMatrix) {
  Trajectory tr = RunDefault(BuildYaml(R"y(model: Rotation
define:
  Rotor:
    parameters:
      w: 1.5
      p: {value: [2, 1], shape: [2]}
    variables:
      phi: {start: 0, fixed: true}
      R: {shape: [2, 2]}
      q: {shape: [2]}
      RtR: {shape: [2, 2]}
      back: {shape: [2]}
    equations:
      - der(phi) = w
      - R = [[cos(phi), -sin(phi)], [sin(phi), cos(phi)]]
      - q = R*p
      - RtR = transpose(R)*R
      - back = p*R
components:
  rotor: {type: Rotor}
experiment: {stop: 3, interval: 0.5, tolerance: 1e-10}
outputs: [rotor.q, rotor.RtR, "rotor.R[2, 1]", rotor.back]
)y"));
  ASSERT_EQ(tr.names, (std::vector<std::string>{"rotor.q[1]", "rotor.q[2]", "rotor.RtR[1,1]", "rotor.RtR[1,2]",
                                                "rotor.RtR[2,1]", "rotor.RtR[2,2]", "rotor.R[2, 1]",
                                                "rotor.back[1]", "rotor.back[2]"}));
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double phi = 1.5 * tr.t[k], c = std::cos(phi), s = std::sin(phi);
    EXPECT_NEAR(tr.Column("rotor.q[1]", k), 2 * c - s, 1e-8);
    EXPECT_NEAR(tr.Column("rotor.q[2]", k), 2 * s + c, 1e-8);
    EXPECT_NEAR(tr.Column("rotor.RtR[1,1]", k), 1, 1e-12);
    EXPECT_NEAR(tr.Column("rotor.RtR[1,2]", k), 0, 1e-12);
    EXPECT_NEAR(tr.Column("rotor.RtR[2,1]", k), 0, 1e-12);
    EXPECT_NEAR(tr.Column("rotor.RtR[2,2]", k), 1, 1e-12);
    EXPECT_NEAR(tr.Column("rotor.R[2, 1]", k), s, 1e-8);
    // p*R is the row vector p^T R.
    EXPECT_NEAR(tr.Column("rotor.back[1]", k), 2 * c + s, 1e-8);
    EXPECT_NEAR(tr.Column("rotor.back[2]", k), -2 * s + c, 1e-8);
  }
}

TEST(ArraysTest, CrossNormSumIdentityZerosAgainstHandValues) {
  Trajectory tr = RunDefault(BuildYaml(R"y(model: Functions
parameters:
  a: [1, 2, 3]
  b: {value: [4, 5, 6], shape: [3]}
variables:
  c: {shape: [3]}
  n: {}
  s: {}
  d: {}
  z: {shape: [2, 3]}
  Ia: {shape: [3]}
  e: {}
equations:
  - c = cross(a, b)
  - n = norm(a)
  - s = sum(b - a) + sum([[1, 2], [3, 4]])
  - d = a*b
  - z = zeros(2, 3) + [[1, 0, 0], [0, 0, 2]]
  - Ia = identity(3)*a/2 - zeros(3)
  - e = a[3]*b[1] - 2*a[2]
experiment: {stop: 1, interval: 1}
outputs: [c, n, s, d, z, Ia, e]
)y"));
  const size_t k = 0;
  EXPECT_DOUBLE_EQ(tr.Column("c[1]", k), -3);  // (2*6 - 3*5, 3*4 - 1*6, 1*5 - 2*4)
  EXPECT_DOUBLE_EQ(tr.Column("c[2]", k), 6);
  EXPECT_DOUBLE_EQ(tr.Column("c[3]", k), -3);
  EXPECT_DOUBLE_EQ(tr.Column("n", k), std::sqrt(14.0));
  EXPECT_DOUBLE_EQ(tr.Column("s", k), 9 + 10);
  EXPECT_DOUBLE_EQ(tr.Column("d", k), 32);
  EXPECT_DOUBLE_EQ(tr.Column("z[1,1]", k), 1);
  EXPECT_DOUBLE_EQ(tr.Column("z[1,2]", k), 0);
  EXPECT_DOUBLE_EQ(tr.Column("z[2,3]", k), 2);
  EXPECT_DOUBLE_EQ(tr.Column("Ia[1]", k), 0.5);
  EXPECT_DOUBLE_EQ(tr.Column("Ia[3]", k), 1.5);
  EXPECT_DOUBLE_EQ(tr.Column("e", k), 12 - 4);
}

// A connector type whose potential and flow are vectors (a library file): connections join
// element by element, an unconnected flow is zero in each element.
TEST(ArraysTest, ConnectorTypeWithVectorVariables) {
  Library lib = BuiltinLibrary();
  LoadLibraryString(R"y(
Frame2:
  kind: connector
  potential: {r: {unit: m, shape: [2]}}
  flow: {f: {unit: N, shape: [2]}}
Anchor:
  parameters: {r0: {value: [1, 2], shape: [2]}}
  connectors: {frame: Frame2}
  equations: [frame.r = r0]
Probe:
  connectors: {frame: Frame2, frame_b: Frame2}
  variables: {d: {shape: [2]}}
  equations:
    - d = frame.r
    - frame_b.r = frame.r
    - frame.f + frame_b.f = zeros(2)
)y", "lib.yaml", &lib);
  const ComponentType* probe = lib.FindComponent("Probe");
  ASSERT_NE(probe, nullptr);
  EXPECT_EQ(probe->arrays.at("frame.r"), (Shape{2}));
  EXPECT_EQ(probe->equations.size(), 6u);
  EXPECT_EQ(probe->equations[0].text, "d = frame.r (element 1)");
  ModelSpec spec = LoadModelString(R"y(model: Frames
components:
  anchor: {type: Anchor, r0: [3, 4]}
  probe: {type: Probe}
connections:
  - [anchor.frame, probe.frame]
)y", "m.yaml");
  FlatSystem flat = Flatten(spec, lib, {});
  std::vector<std::string> texts;
  for (const auto& e : flat.equations) {
    if (e.origin == EquationOrigin::kConnection || e.origin == EquationOrigin::kUnconnectedFlow) texts.push_back(flat.EquationText(e));
  }
  EXPECT_EQ(texts, (std::vector<std::string>{
                       "probe.frame.r[1] = anchor.frame.r[1] (connection)",
                       "probe.frame.r[2] = anchor.frame.r[2] (connection)",
                       "sum of f[1] over {anchor.frame, probe.frame} = 0 (connection)",
                       "sum of f[2] over {anchor.frame, probe.frame} = 0 (connection)",
                       "probe.frame_b.f[1] = 0 (unconnected)",
                       "probe.frame_b.f[2] = 0 (unconnected)"}));
  std::vector<double> values = EvaluateParameters(flat, {});
  std::vector<std::string> names;
  for (uint32_t k = 0; k < flat.parameters.size(); ++k) names.push_back(flat.ParameterName(ParamId(k)));
  EXPECT_EQ(names, (std::vector<std::string>{"anchor.r0[1]", "anchor.r0[2]"}));
  EXPECT_EQ(values, (std::vector<double>{3, 4}));

  // The modifiers of a component inside a type (composite types): values in the type's scope.
  ComponentSpec inner;
  inner.name = "anchor";
  Modifier m;
  m.key = "r0";
  m.value_text = "2*frame.r";
  m.value = ParseExpression(m.value_text, SourceLoc("lib.yaml"));
  inner.modifiers.push_back(m);
  std::vector<Modifier> expanded = ScalarModifiers(inner, *lib.FindComponent("Anchor"), ScopeOf(*probe));
  ASSERT_EQ(expanded.size(), 2u);
  EXPECT_EQ(expanded[1].key, "r0[2]");
  EXPECT_EQ(expanded[1].value_text, "(2 * frame.r[2])");
}

// Arrays in the parts of a composite type: a whole-array modifier inside the type, a whole-array
// output and -p on an element at depth.
TEST(ArraysTest, ArraysInsideCompositeTypes) {
  testing::Built b = BuildYaml(R"y(model: Comp
define:
  Body:
    parameters: {r0: {value: [1, 2], shape: [2]}}
    variables: {r: {shape: [2], start: r0, fixed: true}}
    equations: ["der(r) = [1, 0]"]
  Pair:
    components:
      body: {type: Body, r0: [3, 4]}
components:
  pair: {type: Pair}
experiment: {stop: 1, interval: 1}
outputs: [pair.body.r]
)y");
  Trajectory tr = RunDefault(b, {{"pair.body.r0[1]", 7}});
  ASSERT_EQ(tr.names, (std::vector<std::string>{"pair.body.r[1]", "pair.body.r[2]"}));
  EXPECT_DOUBLE_EQ(tr.Column("pair.body.r[1]", 1), 8);
  EXPECT_DOUBLE_EQ(tr.Column("pair.body.r[2]", 1), 4);
}

// A model without arrays is handed to the flattener as it is.
TEST(ArraysTest, ModelWithoutArraysIsLeftAlone) {
  ModelSpec spec = LoadModelString(R"y(model: Plain
components:
  A: {type: Mass, m: 2}
)y", "m.yaml");
  EXPECT_FALSE(ScalarModel(spec, BuiltinLibrary()).has_value());
}

// ---------------------------------------------------------------------------------------------
// Errors: file:line:col, the user's type or component, both shapes.

std::string BodyError(const std::string& equation, const std::string& extra = "") {
  return BuildError(R"y(model: Bad
define:
  Body:
    parameters:
      A: {value: [[1, 2, 3], [4, 5, 6]], shape: [2, 3]}
    variables:
      r: {shape: [2]}
      x: {}
)y" + extra + R"y(
    equations:
      - )y" + equation + R"y(
      - x = 0
components:
  body: {type: Body}
)y");
}

TEST(ArraysErrorsTest, ShapeMismatchInSumNamesBothShapes) {
  EXPECT_EQ(BodyError("r = r + [1, 2, 3]"),
            "test.yaml:11:17: the operands of '+' have different shapes: [2] and [3], in 'r = r + [1, 2, 3]' of Body");
  EXPECT_EQ(BodyError("r = [1, 2] - 1"),
            "test.yaml:11:22: the operands of '-' have different shapes: [2] and scalar (add arrays of one shape; "
            "scale with * and /), in 'r = [1, 2] - 1' of Body");
}

TEST(ArraysErrorsTest, ShapeMismatchInEquation) {
  EXPECT_EQ(BodyError("r = [1, 2, 3]"),
            "test.yaml:11:13: the two sides of the equation have different shapes: [2] and [3], in 'r = [1, 2, 3]' of Body");
}

TEST(ArraysErrorsTest, MatrixProductInnerDimension) {
  EXPECT_EQ(BodyError("r = A*r"),
            "test.yaml:11:14: product of shapes [2, 3] and [2]: the inner dimensions 3 and 2 differ, in 'r = A*r' of Body");
}

TEST(ArraysErrorsTest, SubscriptOutOfRangeAndNotConstant) {
  EXPECT_EQ(BodyError("r = [r[3], 0]"),
            "test.yaml:11:14: 'r[3]': subscript 3 is out of range 1..2 (r has shape [2]), in 'r = [r[3], 0]' of Body");
  EXPECT_EQ(BodyError("r = [r[x], 0]"),
            "test.yaml:11:14: the subscript 'x' of 'r[x]' must be a constant whole number (a subscript picks a fixed "
            "element), in 'r = [r[x], 0]' of Body");
  EXPECT_NE(BodyError("r = [A[3, 1], 0]").find("'A[3, 1]': subscript 3 is out of range 1..2 (A has shape [2, 3])"),
            std::string::npos);
  EXPECT_EQ(BodyError("r = [x[1], 0]"),
            "test.yaml:11:14: 'x[1]': x is not an array (declare it with shape: [n]), so it has no elements, in "
            "'r = [x[1], 0]' of Body");
}

TEST(ArraysErrorsTest, FunctionsOnTheWrongShape) {
  EXPECT_EQ(BodyError("r = cross(r, r)"),
            "test.yaml:11:13: cross() takes two vectors of shape [3], found shape [2] and shape [2], in "
            "'r = cross(r, r)' of Body");
  EXPECT_EQ(BodyError("r = transpose(r)"),
            "test.yaml:11:13: transpose() takes a matrix, found shape [2], in 'r = transpose(r)' of Body");
  EXPECT_EQ(BodyError("x = norm(x)"), "test.yaml:11:13: norm() takes a vector, found a scalar, in 'x = norm(x)' of Body");
  EXPECT_EQ(BodyError("x = sum(x)"), "test.yaml:11:13: sum() takes an array, found a scalar, in 'x = sum(x)' of Body");
  EXPECT_EQ(BodyError("r = r/r"),
            "test.yaml:11:14: division by an array of shape [2]; only a scalar divides, in 'r = r/r' of Body");
  EXPECT_EQ(BodyError("r = r^2"),
            "test.yaml:11:14: '^' takes scalars, found an operand of shape [2], in 'r = r^2' of Body");
  EXPECT_EQ(BodyError("r = zeros(x)"),
            "test.yaml:11:19: the size 'x' given to zeros() must be a constant whole number from 1 to 100000, in "
            "'r = zeros(x)' of Body");
}

TEST(ArraysErrorsTest, StartAndValueListsOfTheWrongShape) {
  EXPECT_EQ(BuildError(R"y(model: Bad
define:
  Body:
    variables:
      r: {shape: [2], start: [1, 2, 3]}
    equations: ["r = [1, 2]"]
components:
  body: {type: Body}
)y"),
            "test.yaml:5:10: the start value of Body.r has shape [3], but it is declared with shape [2], in "
            "'[1, 2, 3]' of Body");
  EXPECT_EQ(BuildError(R"y(model: Bad
define:
  Body:
    parameters:
      r0: {value: [0, 0], shape: [2]}
    variables: {r: {shape: [2]}}
    equations: ["r = r0"]
components:
  body: {type: Body, r0: [1, 2, 3]}
)y"),
            "test.yaml:9:26: the value of body.r0 has shape [3], but it is declared with shape [2], in '[1, 2, 3]'");
  EXPECT_EQ(BuildError(R"y(model: Bad
define:
  Body:
    parameters:
      r0: {value: [0, 0, 1], shape: [2]}
    variables: {r: {shape: [2]}}
    equations: ["r = r0"]
components:
  body: {type: Body}
)y"),
            "test.yaml:5:19: the value of Body.r0 has shape [3], but it is declared with shape [2], in '[0, 0, 1]' of Body");
  EXPECT_EQ(BuildError(R"y(model: Bad
define:
  Body:
    variables: {r: {shape: [0]}}
components:
  body: {type: Body}
)y"),
            "test.yaml:4:29: a size in the shape of Body.r must be a whole number of at least 1");
}

TEST(ArraysErrorsTest, ArraySyntax) {
  SourceLoc loc("m.yaml");
  loc.line = 3;
  loc.column = 5;
  EXPECT_EQ(AstToString(*ParseExpression("[[1, 2], [3, 4]]*R[1, 2]", loc)), "([[1, 2], [3, 4]] * R[1, 2])");
  auto error = [&](const std::string& text) {
    try {
      ParseExpression(text, loc);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("zeros(1, 2, 3)"), "m.yaml:3:5: zeros() takes 1 or 2 arguments, found 3 in 'zeros(1, 2, 3)'");
  EXPECT_EQ(error("[]"), "m.yaml:3:6: expected the elements of an array, e.g. [1, 2], found ']' in '[]'");
  EXPECT_EQ(error("[1, 2"), "m.yaml:3:10: expected ']' or ',', found end of text in '[1, 2'");
  EXPECT_EQ(error("R[1, 2, 3]"), "m.yaml:3:11: expected ']', found ',' in 'R[1, 2, 3]'");
  const std::string yaml = R"y(model: Bad
define:
  Body:
    variables: {r: {shape: SHAPE}}
    equations: []
components:
  body: {type: Body}
)y";
  auto with = [&](const std::string& shape) { return BuildError(yaml.substr(0, yaml.find("SHAPE")) + shape + yaml.substr(yaml.find("SHAPE") + 5)); };
  EXPECT_EQ(with("2"), "test.yaml:4:28: the shape of Body.r is a list of one or two sizes, e.g. shape: [2] or shape: [3, 3]");
  EXPECT_EQ(with("[2, 2, 2]"), "test.yaml:4:28: the shape of Body.r is a list of one or two sizes, e.g. shape: [2] or shape: [3, 3]");
  EXPECT_EQ(with("[1000, 1000]"), "test.yaml:4:28: the shape of Body.r has more than 100000 elements");
  // Matrix products multiply nodes: bounded, with a message at the place.
  EXPECT_EQ(BuildError(R"y(model: Big
parameters: {A: "zeros(200, 200)"}
variables: {B: {shape: [200, 200]}}
equations: ["B = A*A*A"]
)y"),
            "test.yaml:4:21: the arrays expand to more than 1000000 scalar expression nodes; use smaller arrays or "
            "fewer array operations, in 'B = A*A*A'");
  EXPECT_EQ(BuildError(R"y(model: Bad
parameters: {g: []}
)y"),
            "test.yaml:2:17: value of Bad.g is an empty list; an array has at least one element");
}

TEST(ArraysErrorsTest, VectorSignalsOfDifferentShapes) {
  EXPECT_EQ(BuildError(R"y(model: Bad
define:
  Source:
    connectors: {y: {type: RealOutput, shape: [3]}}
    equations: ["y = [1, 2, 3]"]
  Sink:
    connectors: {u: {type: RealInput, shape: [2]}}
    variables: {x: {shape: [2]}}
    equations: ["x = u"]
components:
  source: {type: Source}
  sink: {type: Sink}
connections:
  - [source.y, sink.u]
)y"),
            "test.yaml:14:6: cannot connect source.y (shape [3]) to sink.u (shape [2]): connected signals must have "
            "the same shape");
}

TEST(ArraysErrorsTest, OnlySignalConnectorsTakeAShape) {
  EXPECT_EQ(BuildError(R"y(model: Bad
define:
  Body:
    connectors: {flange: {type: Flange, shape: [2]}}
    equations: []
components:
  body: {type: Body}
)y"),
            "test.yaml:4:26: Body.flange: only signal connectors take a shape; Flange is a physical connector (give "
            "its type's variables a shape instead)");
}

}  // namespace
}  // namespace momenta
