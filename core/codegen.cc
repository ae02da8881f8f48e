#include "core/codegen.h"

#include <charconv>

#include "core/error.h"

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

/// The C helpers the instructions call: PowValue and InterpolateTable (core/expr_eval.h) written
/// out operation for operation, so that their results agree to the bit.
constexpr const char* kPrelude = R"(#include <math.h>
#include <stddef.h>
#include <stdint.h>

static double m_pow(double x, double y) {
  if (y == 2.0) return x * x;
  if (y == 3.0) return x * x * x;
  if (y == 0.5) return sqrt(x);
  return pow(x, y);
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

/// Emits the functions of one program.
class ProgramEmitter {
 public:
  ProgramEmitter(const RegisterLayout& layout, Writer* w) : layout_(layout), w_(*w) {
    const uint32_t num_temps = layout.size > layout.temp_base ? layout.size - layout.temp_base : 0;
    live_.assign(num_temps, 0);
    in_mark_.assign(num_temps, 0);
    written_mark_.assign(num_temps, 0);
  }

  void Emit(const CodegenProgram& p) {
    const Program& program = *p.program;
    const std::vector<CodeSegment>& segments = p.segments;
    // Which temporaries each segment needs from earlier ones (live in) and leaves for later ones
    // (live out): a backward pass over the segments.
    std::vector<std::vector<uint32_t>> live_in(segments.size()), written(segments.size()),
        live_out(segments.size());
    for (size_t s = 0; s < segments.size(); ++s) {
      MOMENTA_CHECK_MSG(segments[s].count == 1, "loop segments are not emitted yet");
      Scan(program, segments[s], &live_in[s], &written[s]);
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
         << "(double* restrict r, double* restrict out) {\n";
      // Locals: the live-in ones start from the register file.
      ++stamp_;
      for (uint32_t t : live_in[s]) in_mark_[t] = stamp_;
      for (uint32_t t : written[s]) written_mark_[t] = stamp_;
      for (uint32_t t : written[s]) {
        w_ << "  double t" << t;
        if (in_mark_[t] == stamp_) w_ << " = r[" << (layout_.temp_base + t) << "]";
        w_ << ";\n";
      }
      for (uint32_t t : live_in[s]) {
        if (written_mark_[t] != stamp_) w_ << "  const double t" << t << " = r[" << (layout_.temp_base + t) << "];\n";
      }
      const CodeSegment& seg = segments[s];
      for (uint32_t k = seg.begin; k < seg.begin + seg.len; ++k) Statement(program, program.code()[k]);
      for (uint32_t t : live_out[s]) w_ << "  r[" << (layout_.temp_base + t) << "] = t" << t << ";\n";
      w_ << "  (void)r;\n  (void)out;\n}\n\n";
    }
    w_ << "void " << p.symbol << "(double* restrict r, double* restrict out) {\n";
    for (size_t s = 0; s < segments.size(); ++s) {
      w_ << "  " << p.symbol << "_" << static_cast<uint32_t>(s) << "(r, out);\n";
    }
    w_ << "  (void)r;\n  (void)out;\n}\n\n";
  }

 private:
  bool IsTemp(uint32_t reg) const { return reg >= layout_.temp_base && reg - layout_.temp_base < live_.size(); }

  /// The temporaries a segment reads before writing them, and those it writes.
  void Scan(const Program& program, const CodeSegment& seg, std::vector<uint32_t>* live_in,
            std::vector<uint32_t>* written) {
    ++stamp_;
    for (uint32_t k = seg.begin; k < seg.begin + seg.len; ++k) {
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

  /// A register as a C operand: a local for a temporary, the register file otherwise.
  std::string Ref(uint32_t reg) const {
    // Appended piece by piece: `"t" + std::to_string(…)` trips gcc 12's false -Wrestrict.
    std::string ref(IsTemp(reg) ? "t" : "r[");
    ref += std::to_string(IsTemp(reg) ? reg - layout_.temp_base : reg);
    if (!IsTemp(reg)) ref += ']';
    return ref;
  }

  void Statement(const Program& program, const Instruction& in) {
    if (in.op == kStore) {
      w_ << "  out[" << in.dst << "] = " << Ref(in.a) << ";\n";
      return;
    }
    w_ << "  " << Ref(in.dst) << " = ";
    if (in.op == kStoreRegister) {
      w_ << Ref(in.a) << ";\n";
      return;
    }
    const std::string a = Ref(in.a);
    auto binary = [&](const char* op) { w_ << a << " " << op << " " << Ref(in.b); };
    auto call1 = [&](const char* f) { w_ << f << "(" << a << ")"; };
    auto relation = [&](const char* op) { w_ << "(" << a << " " << op << " " << Ref(in.b) << " ? 1.0 : 0.0)"; };
    switch (static_cast<Op>(in.op)) {
      case Op::kAdd: binary("+"); break;
      case Op::kSub: binary("-"); break;
      case Op::kMul: binary("*"); break;
      case Op::kDiv: binary("/"); break;
      case Op::kNeg: w_ << "-" << a; break;
      case Op::kPow: w_ << "m_pow(" << a << ", " << Ref(in.b) << ")"; break;
      case Op::kIf: w_ << "(" << a << " != 0 ? " << Ref(in.b) << " : " << Ref(in.c) << ")"; break;
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
      case Op::kSign: w_ << "(" << a << " > 0 ? 1.0 : (" << a << " < 0 ? -1.0 : 0.0))"; break;
      case Op::kNot: w_ << "(" << a << " != 0 ? 0.0 : 1.0)"; break;
      case Op::kAtan2: w_ << "atan2(" << a << ", " << Ref(in.b) << ")"; break;
      case Op::kMin: w_ << "(" << a << " < " << Ref(in.b) << " ? " << a << " : " << Ref(in.b) << ")"; break;
      case Op::kMax: w_ << "(" << a << " > " << Ref(in.b) << " ? " << a << " : " << Ref(in.b) << ")"; break;
      case Op::kLt: relation("<"); break;
      case Op::kLe: relation("<="); break;
      case Op::kGt: relation(">"); break;
      case Op::kGe: relation(">="); break;
      case Op::kEq: relation("=="); break;
      case Op::kNe: relation("!="); break;
      case Op::kAnd: w_ << "((" << a << " != 0 && " << Ref(in.b) << " != 0) ? 1.0 : 0.0)"; break;
      case Op::kOr: w_ << "((" << a << " != 0 || " << Ref(in.b) << " != 0) ? 1.0 : 0.0)"; break;
      case Op::kInterp:
      case Op::kInterpSlope: {
        // b is the register of the table's element [1,1]; the shape is structure, so a constant.
        const TableShape& t = program.tables().at(in.c);
        w_ << "m_interp(r + " << in.b << ", " << t.rows << "u, " << t.cols << "u, " << t.column << "u, " << a
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
  uint32_t stamp_ = 0;
};

}  // namespace

std::vector<CodeSegment> StraightSegments(const Program& program, uint32_t max_len) {
  MOMENTA_CHECK(max_len > 0);
  std::vector<CodeSegment> out;
  const uint32_t n = static_cast<uint32_t>(program.size());
  for (uint32_t begin = 0; begin < n; begin += max_len) out.push_back({begin, std::min(max_len, n - begin), 1});
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
