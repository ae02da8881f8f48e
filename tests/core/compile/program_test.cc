// Compiled programs against the tree-walking Evaluate() on random expression DAGs (fixed seed):
// shared subexpressions, every operation, if and relations, parameter-only parts (computed by the
// parameter program), and many roots per program so that temporaries are reused.

#include "core/compile/program.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "core/expr/expr_eval.h"

namespace momenta {
namespace {

constexpr uint32_t kVars = 6, kParams = 3;

/// A random DAG: each new node takes its children from the nodes made so far, so subexpressions
/// are shared freely.
class RandomDag {
 public:
  RandomDag(ExprPool* pool, uint32_t seed) : pool_(*pool), rng_(seed) {
    for (uint32_t v = 0; v < kVars; ++v) {
      nodes_.push_back(pool_.Var(VarId(v)));
      nodes_.push_back(pool_.Der(VarId(v)));
      nodes_.push_back(pool_.Pre(VarId(v)));
    }
    for (uint32_t p = 0; p < kParams; ++p) nodes_.push_back(pool_.Param(ParamId(p)));
    nodes_.push_back(pool_.Time());
    nodes_.push_back(pool_.Initial());
    for (double c : {0.5, 2.0, -1.5, 3.0, 0.25}) nodes_.push_back(pool_.Const(c));
    // Parameter-only subexpressions, for the parameter program.
    params_only_ = {pool_.Param(ParamId(0u)), pool_.Param(ParamId(1u)), pool_.Param(ParamId(2u))};
  }

  ExprId Pick() {
    // Prefer recent nodes so that depth grows.
    std::uniform_int_distribution<size_t> recent(nodes_.size() > 40 ? nodes_.size() - 40 : 0, nodes_.size() - 1);
    std::uniform_int_distribution<size_t> any(0, nodes_.size() - 1);
    return rng_() % 3 == 0 ? nodes_[any(rng_)] : nodes_[recent(rng_)];
  }
  ExprId PickParamOnly() { return params_only_[rng_() % params_only_.size()]; }

  ExprId Grow() {
    static const Op kUnary[] = {Op::kNeg, Op::kSin, Op::kCos, Op::kTan, Op::kAsin, Op::kAcos,
                                Op::kAtan, Op::kSinh, Op::kCosh, Op::kTanh, Op::kExp, Op::kLog,
                                Op::kLog10, Op::kSqrt, Op::kAbs, Op::kSign, Op::kFloor, Op::kNot};
    static const Op kBinary[] = {Op::kAdd, Op::kSub, Op::kMul, Op::kDiv, Op::kPow, Op::kAtan2,
                                 Op::kMin, Op::kMax, Op::kLt, Op::kLe, Op::kGt, Op::kGe,
                                 Op::kEq, Op::kNe, Op::kAnd, Op::kOr};
    ExprId e;
    switch (rng_() % 8) {
      case 0:
      case 1: {
        Op op = kUnary[rng_() % (sizeof kUnary / sizeof kUnary[0])];
        // Keep most values finite: exp/sinh/cosh of something bounded.
        ExprId a = Pick();
        if (op == Op::kExp || op == Op::kSinh || op == Op::kCosh) a = pool_.Unary(Op::kSin, a);
        e = pool_.Unary(op, a);
        break;
      }
      case 2:
      case 3:
      case 4: {
        Op op = kBinary[rng_() % (sizeof kBinary / sizeof kBinary[0])];
        ExprId a = Pick(), b = Pick();
        if (op == Op::kPow) b = rng_() % 2 ? pool_.Const(static_cast<double>(rng_() % 4)) : pool_.Unary(Op::kCos, b);
        e = pool_.Binary(op, a, b, rng_() % 4 == 0 ? kNoEvent : 0);
        break;
      }
      case 5:
        e = pool_.If(pool_.Binary(rng_() % 2 ? Op::kLt : Op::kGe, Pick(), Pick()), Pick(), Pick());
        break;
      case 6: {
        // A parameter-only subexpression, then mixed with variables.
        ExprId p = pool_.Binary(rng_() % 2 ? Op::kMul : Op::kAdd, PickParamOnly(),
                                pool_.Unary(Op::kSqrt, PickParamOnly()));
        params_only_.push_back(p);
        e = pool_.Add(p, Pick());
        break;
      }
      default:
        e = pool_.Mul(Pick(), pool_.Add(Pick(), Pick()));
        break;
    }
    nodes_.push_back(e);
    return e;
  }

 private:
  ExprPool& pool_;
  std::mt19937 rng_;
  std::vector<ExprId> nodes_, params_only_;
};

/// Values in registers and for Evaluate(); y is a permutation of the flat variables.
struct Values {
  std::vector<double> vars, ders, pres, params;
  double time = 0.37;
  bool initial = false;
  LeafValues Leaves() const {
    LeafValues lv;
    lv.vars = vars.data();
    lv.ders = ders.data();
    lv.pres = pres.data();
    lv.params = params.data();
    lv.time = time;
    lv.initial = initial;
    return lv;
  }
};

bool SameDouble(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::memcmp(&a, &b, sizeof a) == 0 || a == b;  // +0 and -0 compare equal
}

class ProgramTest : public ::testing::TestWithParam<uint32_t> {};

TEST_P(ProgramTest, CompiledProgramsMatchEvaluate) {
  const uint32_t seed = GetParam();
  ExprPool pool;
  RandomDag dag(&pool, seed);
  std::vector<ExprId> all;
  for (int k = 0; k < 400; ++k) all.push_back(dag.Grow());
  // Two programs over the same registers: many roots (with repeats, leaves and constants among
  // them), and a few deep ones.
  std::mt19937 rng(seed * 7 + 1);
  std::vector<ExprId> roots_a, roots_b;
  for (int k = 0; k < 150; ++k) roots_a.push_back(all[rng() % all.size()]);
  roots_a.push_back(roots_a[3]);
  roots_a.push_back(pool.Var(VarId(2u)));
  roots_a.push_back(pool.Param(ParamId(1u)));
  roots_a.push_back(pool.Const(4.5));
  roots_a.push_back(pool.Mul(pool.Param(ParamId(0u)), pool.Param(ParamId(2u))));
  for (size_t k = all.size() - 10; k < all.size(); ++k) roots_b.push_back(all[k]);
  roots_b.push_back(pool.Der(VarId(5u)));
  roots_b.push_back(pool.Pre(VarId(0u)));
  roots_b.push_back(pool.Time());
  roots_b.push_back(pool.Initial());

  // y positions: a permutation of the flat variables.
  std::vector<int32_t> y_index = {3, 0, 5, 1, 4, 2};
  ProgramCompiler compiler(pool, kParams, y_index, std::vector<int32_t>(kVars, -1), 0);
  Program a = compiler.Compile(roots_a);
  Program b = compiler.Compile(roots_b);
  compiler.Finish({&a, &b, &compiler.parameter_program()});
  const RegisterLayout& L = compiler.layout();
  EXPECT_EQ(L.num_unknowns, kVars);
  EXPECT_EQ(L.num_params, kParams);

  std::uniform_real_distribution<double> value(-2.0, 2.0);
  for (int trial = 0; trial < 5; ++trial) {
    Values v;
    v.vars.resize(kVars);
    v.ders.resize(kVars);
    v.pres.resize(kVars);
    v.params = {value(rng), std::fabs(value(rng)), value(rng)};
    for (uint32_t k = 0; k < kVars; ++k) {
      v.vars[k] = value(rng);
      v.ders[k] = value(rng);
      v.pres[k] = value(rng);
    }
    // Integers now and then, so that == and <> and the pow cases are exercised.
    if (trial == 1) v.vars[0] = v.vars[1] = 1.0;
    v.time = 0.1 * trial;
    v.initial = trial % 2 == 0;
    // Fill the registers as ModelState does.
    std::vector<double> regs(L.size, std::nan(""));
    regs[RegisterLayout::kTime] = v.time;
    regs[RegisterLayout::kCj] = 0;
    regs[RegisterLayout::kInitial] = v.initial ? 1.0 : 0.0;
    for (const auto& [reg, c] : compiler.constants()) regs[reg] = c;
    for (uint32_t p = 0; p < kParams; ++p) regs[L.param_base + p] = v.params[p];
    for (uint32_t k = 0; k < kVars; ++k) {
      regs[L.y_base + y_index[k]] = v.vars[k];
      regs[L.yp_base + y_index[k]] = v.ders[k];
      regs[L.pre_base + y_index[k]] = v.pres[k];
    }
    compiler.parameter_program().Run(regs.data(), nullptr);
    std::vector<double> out_a(roots_a.size(), -777), out_b(roots_b.size(), -777);
    // b first: a program must not depend on another having run before it.
    b.Run(regs.data(), out_b.data());
    a.Run(regs.data(), out_a.data());
    LeafValues lv = v.Leaves();
    for (size_t k = 0; k < roots_a.size(); ++k) {
      double want = Evaluate(pool, roots_a[k], lv);
      EXPECT_TRUE(SameDouble(out_a[k], want)) << "seed " << seed << " trial " << trial << " root " << k
                                              << ": compiled " << out_a[k] << ", evaluated " << want;
    }
    for (size_t k = 0; k < roots_b.size(); ++k) {
      double want = Evaluate(pool, roots_b[k], lv);
      EXPECT_TRUE(SameDouble(out_b[k], want)) << "seed " << seed << " trial " << trial << " deep root " << k
                                              << ": compiled " << out_b[k] << ", evaluated " << want;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, ProgramTest, ::testing::Values(1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u));

TEST(NodeArrayTest, NewElementsAreZeroAndGrowingKeepsTheOthers) {
  NodeArray a;
  EXPECT_EQ(a.size(), 0u);
  a.Grow(10);
  ASSERT_GE(a.size(), 10u);
  for (size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], 0u);
  for (size_t k = 0; k < 10; ++k) a[k] = static_cast<uint32_t>(k + 1);
  // Past a million elements (moved by mremap): the old values stay, the new ones are zero.
  a.Grow(3u << 20);
  ASSERT_GE(a.size(), 3u << 20);
  for (size_t k = 0; k < 10; ++k) EXPECT_EQ(a[k], k + 1);
  EXPECT_EQ(a[10], 0u);
  EXPECT_EQ(a[(3u << 20) - 1], 0u);
  a[(3u << 20) - 1] = 7;
  a.Release();
  EXPECT_EQ(a.size(), 0u);
  a.Grow(4);
  EXPECT_EQ(a[3], 0u);
}

TEST(ProgramCompilerTest, TemporariesAreReused) {
  // A balanced sum of 1024 products: 1024 intermediate values, but at most ~log2(1024) of them
  // alive at a time.
  ExprPool pool;
  std::vector<ExprId> level;
  for (uint32_t k = 0; k < 1024; ++k) {
    level.push_back(pool.Mul(pool.Var(VarId(k % kVars)), pool.Const(k + 2.0)));
  }
  while (level.size() > 1) {
    std::vector<ExprId> next;
    for (size_t k = 0; k + 1 < level.size(); k += 2) next.push_back(pool.Add(level[k], level[k + 1]));
    level.swap(next);
  }
  std::vector<int32_t> y_index = {0, 1, 2, 3, 4, 5};
  ProgramCompiler compiler(pool, 0, y_index, std::vector<int32_t>(kVars, -1), 0);
  Program prog = compiler.Compile({level[0]});
  compiler.Finish({&prog});
  const RegisterLayout& L = compiler.layout();
  EXPECT_LT(L.size - L.temp_base, 40u) << "temporaries are not reused";
  EXPECT_EQ(prog.size(), 1024u + 1023u + 1u);  // products, sums, the store
  // Its size is known before it is emitted: it holds no room to grow (a model's programs are
  // most of the memory at the end of a build).
  EXPECT_EQ(prog.code().capacity(), prog.size());
  std::vector<double> regs(L.size, 0.0);
  for (const auto& [reg, c] : compiler.constants()) regs[reg] = c;
  double want = 0;
  for (uint32_t k = 0; k < 1024; ++k) want += (k % kVars + 1.0) * (k + 2.0);
  for (uint32_t v = 0; v < kVars; ++v) regs[L.y_base + v] = v + 1.0;
  double out = 0;
  prog.Run(regs.data(), &out);
  EXPECT_DOUBLE_EQ(out, want);
}

TEST(ProgramCompilerTest, DeepExpressionCompilesWithoutRecursion) {
  // A 100 000-deep chain (a chain of rods' offsets, a long flow sum).
  ExprPool pool;
  ExprId e = pool.Var(VarId(0u));
  for (int k = 0; k < 100000; ++k) e = pool.Add(pool.Mul(e, pool.Const(0.5)), pool.Var(VarId(1u)));
  ProgramCompiler compiler(pool, 0, {0, 1}, {-1, -1}, 0);
  Program prog = compiler.Compile({e});
  compiler.Finish({&prog});
  const RegisterLayout& L = compiler.layout();
  EXPECT_LT(L.size - L.temp_base, 8u);
  std::vector<double> regs(L.size, 0.0);
  for (const auto& [reg, c] : compiler.constants()) regs[reg] = c;
  regs[L.y_base] = 4;
  regs[L.y_base + 1] = 1;
  double out = 0;
  prog.Run(regs.data(), &out);
  // x_{k+1} = x_k/2 + 1 converges to 2.
  EXPECT_NEAR(out, 2.0, 1e-12);
}

TEST(ProgramCompilerTest, ParameterOnlyPartsRunOncePerParameterSet) {
  ExprPool pool;
  ExprId p = pool.Param(ParamId(0u)), q = pool.Param(ParamId(1u));
  ExprId heavy = pool.Unary(Op::kSqrt, pool.Add(pool.Mul(p, p), pool.Mul(q, q)));
  ExprId x = pool.Var(VarId(0u));
  ProgramCompiler compiler(pool, 2, {0}, {-1}, 0);
  Program prog = compiler.Compile({pool.Mul(heavy, x), pool.Div(x, heavy), heavy});
  compiler.Finish({&prog, &compiler.parameter_program()});
  // The residual program only multiplies and divides (and stores); the square root and its
  // operands are in the parameter program.
  for (const Instruction& in : prog.code()) {
    EXPECT_TRUE(in.op == static_cast<uint8_t>(Op::kMul) || in.op == static_cast<uint8_t>(Op::kDiv) ||
                in.op == kStore)
        << OpName(static_cast<Op>(in.op));
  }
  EXPECT_EQ(compiler.parameter_program().size(), 4u);  // p*p, q*q, +, sqrt
  const RegisterLayout& L = compiler.layout();
  std::vector<double> regs(L.size, 0.0);
  for (const auto& [reg, c] : compiler.constants()) regs[reg] = c;
  regs[L.param_base] = 3;
  regs[L.param_base + 1] = 4;
  regs[L.y_base] = 10;
  compiler.parameter_program().Run(regs.data(), nullptr);
  double out[3];
  prog.Run(regs.data(), out);
  EXPECT_DOUBLE_EQ(out[0], 50);
  EXPECT_DOUBLE_EQ(out[1], 2);
  EXPECT_DOUBLE_EQ(out[2], 5);
}

}  // namespace
}  // namespace momenta
