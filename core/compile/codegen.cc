#include "core/compile/codegen.h"

#include <charconv>

#include "core/base/error.h"
#include "core/compile/reroll.h"

namespace momenta {

namespace {

/// The registers an instruction reads (as Program::Run reads them) and whether it writes one.
/// An interpolation also reads its table from register b on, but tables are parameters, never
/// temporaries, so only its abscissa a counts here.
struct Access {
  uint32_t reads[3] = {0, 0, 0};
  int num_reads = 0;
  bool writes_register = true;  ///< false: kStore writes out[dst]
};

Access AccessOf(const Instruction& in) {
  Access acc;
  auto read = [&](uint32_t reg) { acc.reads[acc.num_reads++] = reg; };
  if (in.op == kStore || in.op == kStoreRegister) {
    read(in.a);
    acc.writes_register = in.op == kStoreRegister;
    return acc;
  }
  switch (static_cast<Op>(in.op)) {
    case Op::kInterp:
    case Op::kInterpSlope:
      read(in.a);
      break;
    case Op::kIf:
      read(in.a);
      read(in.b);
      read(in.c);
      break;
    default:
      read(in.a);
      if (Arity(static_cast<Op>(in.op)) >= 2) read(in.b);
      break;
  }
  return acc;
}

/// Appends text and numbers to a growing C file; the files for large models run to megabytes, so
/// no streams.
class Writer {
 public:
  Writer& operator<<(const char* s) {
    text_ += s;
    return *this;
  }
  Writer& operator<<(const std::string& s) {
    text_ += s;
    return *this;
  }
  Writer& operator<<(uint32_t v) {
    char buf[16];
    auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
    text_.append(buf, end);
    return *this;
  }
  std::string& text() { return text_; }

 private:
  std::string text_;
};

/// The C helpers the instructions call: PowValue (core/expr/ops.h) and InterpolateTable
/// (core/expr/expr_eval.h) written out operation for operation, so that their results agree to the
/// bit.
constexpr const char* kPrelude = R"(#include <math.h>
#include <stddef.h>
#include <stdint.h>

static double m_pow(double x, double y) {
  if (y == 2.0) return x * x;
  if (y == 3.0) return x * x * x;
  if (y == 0.5) return sqrt(x);
  return pow(x, y);
}

/* Register k of a loop whose repetitions cross from one array into another: y and y' are read
   where the caller keeps them, the rest from the register file. */
static double m_reg(const double* r, const double* y, const double* yp, uint32_t k, uint32_t y_base,
                    uint32_t yp_base, uint32_t n) {
  if (k - y_base < n) return y[k - y_base];
  if (k - yp_base < n) return yp[k - yp_base];
  return r[k];
}

static double m_interp(const double* table, uint32_t rows, uint32_t cols, uint32_t column,
                       double x, int slope) {
  const double* y = table + (column - 1);
  if (rows == 1) return slope ? 0.0 : y[0];
  uint32_t lo = 0, hi = rows - 1;
  while (hi - lo > 1) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (x >= table[(size_t)mid * cols]) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const double x0 = table[(size_t)lo * cols], x1 = table[(size_t)hi * cols];
  const double y0 = y[(size_t)lo * cols], y1 = y[(size_t)hi * cols];
  const double k = (y1 - y0) / (x1 - x0);
  return slope ? k : y0 + k * (x - x0);
}

)";

/// Every generated function's parameters: the register file, y and y' where the caller keeps
/// them (ModelState passes IDA's vectors to the residual and the Jacobian without copying them
/// into the registers; the y and y' registers are never read), and the outputs.
constexpr const char* kParameters =
    "double* restrict r, const double* restrict y, const double* restrict yp, double* restrict out";
constexpr const char* kUnused = "  (void)r, (void)y, (void)yp, (void)out;\n";

/// Emits the functions of one program.
class ProgramEmitter {
 public:
  ProgramEmitter(const RegisterLayout& layout, Writer* w) : layout_(layout), w_(*w) {
    const uint32_t num_temps = layout.size > layout.temp_base ? layout.size - layout.temp_base : 0;
    live_.assign(num_temps, 0);
    in_mark_.assign(num_temps, 0);
    written_mark_.assign(num_temps, 0);
    memory_mark_.assign(num_temps, 0);
  }

  void Emit(const CodegenProgram& p) {
    const Program& program = *p.program;
    const std::vector<CodeSegment>& segments = p.segments;
    // Which temporaries each segment needs from earlier ones (live in) and leaves for later ones
    // (live out): a backward pass over the segments. A loop is scanned as the straight-line code
    // it stands for (the program holds it expanded), so its liveness is exact.
    std::vector<std::vector<uint32_t>> live_in(segments.size()), written(segments.size()),
        live_out(segments.size()), in_memory(segments.size());
    for (size_t s = 0; s < segments.size(); ++s) {
      const CodeSegment& seg = segments[s];
      MOMENTA_CHECK(seg.count >= 1 && (seg.count == 1 || seg.stride.size() == seg.len));
      Scan(program, seg, &live_in[s], &written[s]);
      if (seg.count > 1) MovingTemporaries(program, seg, &in_memory[s]);
    }
    std::fill(live_.begin(), live_.end(), 0);
    for (size_t s = segments.size(); s-- > 0;) {
      for (uint32_t t : written[s]) {
        if (live_[t]) live_out[s].push_back(t);
        live_[t] = 0;
      }
      for (uint32_t t : live_in[s]) live_[t] = 1;
    }
    // One function per segment, then the entry point calling them in order.
    for (size_t s = 0; s < segments.size(); ++s) {
      w_ << "static __attribute__((noinline)) void " << p.symbol << "_" << static_cast<uint32_t>(s)
         << "(" << kParameters << ") {\n";
      // Locals: the live-in ones start from the register file. Temporaries a loop keeps in the
      // register file are none of them (they are there already).
      ++stamp_;
      for (uint32_t t : in_memory[s]) memory_mark_[t] = stamp_;
      for (uint32_t t : live_in[s]) in_mark_[t] = stamp_;
      for (uint32_t t : written[s]) written_mark_[t] = stamp_;
      for (uint32_t t : written[s]) {
        if (memory_mark_[t] == stamp_) continue;
        w_ << "  double t" << t;
        if (in_mark_[t] == stamp_) w_ << " = r[" << (layout_.temp_base + t) << "]";
        w_ << ";\n";
      }
      for (uint32_t t : live_in[s]) {
        if (written_mark_[t] != stamp_ && memory_mark_[t] != stamp_) {
          w_ << "  const double t" << t << " = r[" << (layout_.temp_base + t) << "];\n";
        }
      }
      const CodeSegment& seg = segments[s];
      if (seg.count == 1) {
        for (uint32_t k = seg.begin; k < seg.begin + seg.len; ++k) Statement(program, program.code()[k], nullptr, "  ");
      } else {
        count_ = seg.count;
        w_ << "  for (ptrdiff_t i = 0; i < " << seg.count << "; ++i) {\n";
        for (uint32_t j = 0; j < seg.len; ++j) Statement(program, program.code()[seg.begin + j], &seg.stride[j], "    ");
        w_ << "  }\n";
      }
      for (uint32_t t : live_out[s]) {
        if (memory_mark_[t] != stamp_) w_ << "  r[" << (layout_.temp_base + t) << "] = t" << t << ";\n";
      }
      w_ << kUnused << "}\n\n";
    }
    w_ << "void " << p.symbol << "(" << kParameters << ") {\n";
    for (size_t s = 0; s < segments.size(); ++s) {
      w_ << "  " << p.symbol << "_" << static_cast<uint32_t>(s) << "(r, y, yp, out);\n";
    }
    w_ << kUnused << "}\n\n";
  }

 private:
  bool IsTemp(uint32_t reg) const { return reg >= layout_.temp_base && reg - layout_.temp_base < live_.size(); }

  /// The temporaries a segment reads before writing them, and those it writes.
  void Scan(const Program& program, const CodeSegment& seg, std::vector<uint32_t>* live_in,
            std::vector<uint32_t>* written) {
    ++stamp_;
    for (uint32_t k = seg.begin; k < seg.begin + seg.len * seg.count; ++k) {
      const Instruction& in = program.code()[k];
      const Access acc = AccessOf(in);
      for (int j = 0; j < acc.num_reads; ++j) {
        if (!IsTemp(acc.reads[j])) continue;
        const uint32_t t = acc.reads[j] - layout_.temp_base;
        if (written_mark_[t] != stamp_ && in_mark_[t] != stamp_) {
          in_mark_[t] = stamp_;
          live_in->push_back(t);
        }
      }
      if (acc.writes_register && IsTemp(in.dst)) {
        const uint32_t t = in.dst - layout_.temp_base;
        if (written_mark_[t] != stamp_) {
          written_mark_[t] = stamp_;
          written->push_back(t);
        }
      }
    }
  }

  /// The temporaries a loop reaches through an operand whose register moves with the repetition:
  /// they stay in the register file for the whole segment (a local cannot be indexed by i), and
  /// so do the same temporaries where an operand with stride 0 names them.
  void MovingTemporaries(const Program& program, const CodeSegment& seg, std::vector<uint32_t>* out) {
    ++stamp_;
    const Instruction* code = program.code().data() + seg.begin;
    auto add = [&](uint32_t reg) {
      if (!IsTemp(reg) || memory_mark_[reg - layout_.temp_base] == stamp_) return;
      memory_mark_[reg - layout_.temp_base] = stamp_;
      out->push_back(reg - layout_.temp_base);
    };
    for (uint32_t j = 0; j < seg.len; ++j) {
      const Instruction& body = code[j];
      const Instruction& step = seg.stride[j];
      const Access acc = AccessOf(body);
      // AccessOf's reads are fields a, b, c in that order (as many as it reads).
      const uint32_t read_strides[3] = {step.a, step.b, step.c};
      for (int f = 0; f < acc.num_reads; ++f) {
        if (read_strides[f] == 0) continue;
        for (uint32_t i = 0; i < seg.count; ++i) {
          const Instruction& in = code[i * seg.len + j];
          add(f == 0 ? in.a : f == 1 ? in.b : in.c);
        }
      }
      if (acc.writes_register && step.dst != 0) {
        for (uint32_t i = 0; i < seg.count; ++i) add(code[i * seg.len + j].dst);
      }
    }
  }

  /// A register as a C operand: a local for a temporary, y[] or yp[] for an unknown or its
  /// derivative, the register file otherwise. In a loop (`step` not 0) the register of
  /// repetition i is reg + i*step modulo 2^32, which is what unsigned 32-bit arithmetic in C
  /// computes.
  std::string Ref(uint32_t reg, uint32_t step = 0) const {
    if (step != 0) return Indexed(reg, step);
    const bool local = IsTemp(reg) && memory_mark_[reg - layout_.temp_base] != stamp_;
    if (local) return "t" + std::to_string(reg - layout_.temp_base);
    const Block b = BlockOf(reg);
    // Appended piece by piece: `"t" + std::to_string(…)` trips gcc 12's false -Wrestrict.
    std::string ref(b.array);
    ref += '[';
    ref += std::to_string(reg - b.base);
    ref += ']';
    return ref;
  }

  /// A register written: no program writes y or y' (they are inputs), so it is a local or r[].
  std::string Target(uint32_t reg, uint32_t step) const {
    const int64_t last = LastRepetition(reg, step);
    MOMENTA_CHECK_MSG(BlockOf(reg).base == 0 && (last < 0 || RunOf(static_cast<uint32_t>(last)) == RunOf(reg)),
                      "a program writes an unknown's register");
    return step != 0 ? "r[" + Affine(reg, step) + "]" : Ref(reg);
  }

  /// An array the registers are read from: r from 0, y from y_base, yp from yp_base.
  struct Block {
    const char* array;
    uint32_t base;
  };
  /// Which run of consecutive registers of one array `reg` lies in: 0 before y, 1 y, 2 between
  /// y and y' (if anything is), 3 y', 4 after y'. A loop's operand whose first and last
  /// repetitions lie in one run stays in it (its index is monotonic in i); runs 0 and 4 are both
  /// r, but a loop from one to the other would pass through y and y'.
  int RunOf(uint32_t reg) const {
    if (reg < layout_.y_base) return 0;
    if (reg - layout_.y_base < layout_.num_unknowns) return 1;
    if (reg < layout_.yp_base) return 2;
    if (reg - layout_.yp_base < layout_.num_unknowns) return 3;
    return 4;
  }
  Block BlockOf(uint32_t reg) const {
    switch (RunOf(reg)) {
      case 1: return {"y", layout_.y_base};
      case 3: return {"yp", layout_.yp_base};
      default: return {"r", 0};
    }
  }
  /// The register of a loop's last repetition, reg + (count - 1)·step with the step read as
  /// signed; -1 when that falls outside 0 … 2^32 - 1 (the index wraps). `reg` itself outside a
  /// loop.
  int64_t LastRepetition(uint32_t reg, uint32_t step) const {
    const int64_t last = static_cast<int64_t>(reg) + static_cast<int64_t>(static_cast<int32_t>(step)) *
                                                     (static_cast<int64_t>(count_) - 1);
    return step == 0 ? reg : (last >= 0 && last <= static_cast<int64_t>(UINT32_MAX) ? last : -1);
  }

  /// The register reg + i*step of a loop's repetition i. When the first and the last
  /// repetition's lie in one run of an array (RunOf) and signed arithmetic reaches the last one
  /// without wrapping, every repetition's does (the index is monotonic in i); otherwise m_reg
  /// picks the array at run time.
  std::string Indexed(uint32_t reg, uint32_t step) const {
    const int64_t last = LastRepetition(reg, step);
    const Block first = BlockOf(reg);
    if (last >= 0 && RunOf(static_cast<uint32_t>(last)) == RunOf(reg)) {
      std::string ref(first.array);
      ref += '[';
      ref += Affine(reg - first.base, step);
      ref += ']';
      return ref;
    }
    return "m_reg(r, y, yp, " + Affine(reg, step) + ", " + std::to_string(layout_.y_base) + "u, " +
           std::to_string(layout_.yp_base) + "u, " + std::to_string(layout_.num_unknowns) + "u)";
  }

  /// reg + i*step modulo 2^32 as a C index. Where the signed step keeps every repetition's value
  /// between 0 and 2^32 (always, in practice), plain signed arithmetic on the loop counter gives
  /// the same values, and the compiler can step the addresses (induction variables); otherwise
  /// unsigned 32-bit arithmetic, which wraps as the definition does.
  std::string Affine(uint32_t base, uint32_t step) const {
    const int64_t signed_step = static_cast<int32_t>(step);
    const int64_t last = static_cast<int64_t>(base) + signed_step * (static_cast<int64_t>(count_) - 1);
    std::string e = std::to_string(base);
    if (last >= 0 && last <= static_cast<int64_t>(UINT32_MAX)) {
      e += signed_step < 0 ? " - " : " + ";
      e += std::to_string(signed_step < 0 ? -signed_step : signed_step);
      e += " * i";
    } else {
      e = "(uint32_t)(" + e + "u + " + std::to_string(step) + "u * (uint32_t)i)";
    }
    return e;
  }

  /// One instruction as a C statement; `step` (in a loop) holds its operands' strides.
  void Statement(const Program& program, const Instruction& in, const Instruction* step, const char* indent) {
    static const Instruction kStraight{0, 0, 0, 0, 0};
    const Instruction& st = step ? *step : kStraight;
    if (in.op == kStore) {
      w_ << indent << "out[" << (st.dst ? Affine(in.dst, st.dst) : std::to_string(in.dst)) << "] = " << Ref(in.a, st.a)
         << ";\n";
      return;
    }
    w_ << indent << Target(in.dst, st.dst) << " = ";
    if (in.op == kStoreRegister) {
      w_ << Ref(in.a, st.a) << ";\n";
      return;
    }
    const std::string a = Ref(in.a, st.a);
    const std::string b = Ref(in.b, st.b);
    auto binary = [&](const char* op) { w_ << a << " " << op << " " << b; };
    auto call1 = [&](const char* f) { w_ << f << "(" << a << ")"; };
    auto relation = [&](const char* op) { w_ << "(" << a << " " << op << " " << b << " ? 1.0 : 0.0)"; };
    switch (static_cast<Op>(in.op)) {
      case Op::kAdd: binary("+"); break;
      case Op::kSub: binary("-"); break;
      case Op::kMul: binary("*"); break;
      case Op::kDiv: binary("/"); break;
      case Op::kNeg: w_ << "-" << a; break;
      case Op::kPow: w_ << "m_pow(" << a << ", " << b << ")"; break;
      case Op::kIf: w_ << "(" << a << " != 0 ? " << b << " : " << Ref(in.c, st.c) << ")"; break;
      case Op::kSin: call1("sin"); break;
      case Op::kCos: call1("cos"); break;
      case Op::kTan: call1("tan"); break;
      case Op::kAsin: call1("asin"); break;
      case Op::kAcos: call1("acos"); break;
      case Op::kAtan: call1("atan"); break;
      case Op::kSinh: call1("sinh"); break;
      case Op::kCosh: call1("cosh"); break;
      case Op::kTanh: call1("tanh"); break;
      case Op::kExp: call1("exp"); break;
      case Op::kLog: call1("log"); break;
      case Op::kLog10: call1("log10"); break;
      case Op::kSqrt: call1("sqrt"); break;
      case Op::kAbs: call1("fabs"); break;
      case Op::kFloor: call1("floor"); break;
      case Op::kSign: w_ << "(" << a << " > 0 ? 1.0 : (" << a << " < 0 ? -1.0 : 0.0))"; break;
      case Op::kNot: w_ << "(" << a << " != 0 ? 0.0 : 1.0)"; break;
      case Op::kAtan2: w_ << "atan2(" << a << ", " << b << ")"; break;
      case Op::kMin: w_ << "(" << a << " < " << b << " ? " << a << " : " << b << ")"; break;
      case Op::kMax: w_ << "(" << a << " > " << b << " ? " << a << " : " << b << ")"; break;
      case Op::kLt: relation("<"); break;
      case Op::kLe: relation("<="); break;
      case Op::kGt: relation(">"); break;
      case Op::kGe: relation(">="); break;
      case Op::kEq: relation("=="); break;
      case Op::kNe: relation("!="); break;
      case Op::kAnd: w_ << "((" << a << " != 0 && " << b << " != 0) ? 1.0 : 0.0)"; break;
      case Op::kOr: w_ << "((" << a << " != 0 || " << b << " != 0) ? 1.0 : 0.0)"; break;
      case Op::kInterp:
      case Op::kInterpSlope: {
        // b is the register of the table's element [1,1]; the shape is structure, so a constant
        // (LoopSegments keeps loops whose shapes change straight).
        const TableShape& t = program.tables().at(in.c);
        w_ << "m_interp(r + ";
        if (st.b) {
          w_ << "(" << Affine(in.b, st.b) << ")";
        } else {
          w_ << in.b;
        }
        w_ << ", " << t.rows << "u, " << t.cols << "u, " << t.column << "u, " << a
           << ", " << (in.op == static_cast<uint8_t>(Op::kInterpSlope) ? "1" : "0") << ")";
        break;
      }
      default:
        // What ApplyUnary gives for an operation it does not know.
        w_ << "__builtin_nan(\"\")";
        break;
    }
    w_ << ";\n";
  }

  const RegisterLayout& layout_;
  Writer& w_;
  std::vector<uint8_t> live_;
  // Per temporary: the stamp of the segment that reads it first / writes it (no clearing needed).
  std::vector<uint32_t> in_mark_, written_mark_;
  /// Per temporary: the stamp of the loop segment that keeps it in the register file.
  std::vector<uint32_t> memory_mark_;
  uint32_t stamp_ = 0;
  uint32_t count_ = 1;  ///< repetitions of the loop being emitted
};

}  // namespace

std::vector<CodeSegment> StraightSegments(const Program& program, uint32_t max_len) {
  MOMENTA_CHECK(max_len > 0);
  std::vector<CodeSegment> out;
  const uint32_t n = static_cast<uint32_t>(program.size());
  for (uint32_t begin = 0; begin < n; begin += max_len) out.push_back({begin, std::min(max_len, n - begin), 1, {}});
  return out;
}

namespace {

/// Whether every repetition of the loop's interpolations reads a table of the body's shape.
bool SameTableShapes(const Program& program, const LoopSegment& loop) {
  for (uint32_t j = 0; j < loop.len; ++j) {
    const Instruction& body = program.code()[loop.begin + j];
    const bool interp = body.op == static_cast<uint8_t>(Op::kInterp) || body.op == static_cast<uint8_t>(Op::kInterpSlope);
    if (!interp || loop.stride[j].c == 0) continue;
    const TableShape& t = program.tables().at(body.c);
    for (uint32_t i = 1; i < loop.count; ++i) {
      const TableShape& u = program.tables().at(program.code()[loop.begin + i * loop.len + j].c);
      if (u.rows != t.rows || u.cols != t.cols || u.column != t.column) return false;
    }
  }
  return true;
}

}  // namespace

std::vector<CodeSegment> LoopSegments(const Program& program, uint32_t max_len) {
  MOMENTA_CHECK(max_len > 0);
  std::vector<CodeSegment> out;
  // Straight-line code not emitted yet: [straight, end).
  uint32_t straight = 0, end = 0;
  auto flush = [&] {
    for (uint32_t b = straight; b < end; b += max_len) out.push_back({b, std::min(max_len, end - b), 1, {}});
    straight = end;
  };
  for (LoopSegment& s : Reroll(program)) {
    end = s.begin + s.len * s.count;
    if (s.count > 1 && s.len <= max_len && SameTableShapes(program, s)) {
      const uint32_t loop_end = end;
      end = s.begin;
      flush();
      out.push_back({s.begin, s.len, s.count, std::move(s.stride)});
      straight = end = loop_end;
    }
  }
  flush();
  return out;
}

std::string SanitizeComment(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    // A '/' next to a '*' could open or close a comment: '/' becomes '|' wherever it stands.
    if (c == '/') {
      out += '|';
    } else {
      out += (c >= 0x20 && c < 0x7f) ? ch : '?';
    }
  }
  return out;
}

std::string EmitC(const std::vector<CodegenProgram>& programs, const RegisterLayout& layout,
                  const CodegenOptions& options) {
  Writer w;
  w << "/* momenta model code: " << SanitizeComment(options.comment) << " */\n" << kPrelude;
  if (!options.key.empty()) w << "const char momenta_key[] = \"" << SanitizeComment(options.key) << "\";\n\n";
  ProgramEmitter emitter(layout, &w);
  for (const CodegenProgram& p : programs) {
    CodegenProgram q = p;
    if (q.segments.empty()) q.segments = StraightSegments(*p.program, options.max_function_len);
    emitter.Emit(q);
  }
  return std::move(w.text());
}

}  // namespace momenta
