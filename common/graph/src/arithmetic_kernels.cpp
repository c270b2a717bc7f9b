#include <cmath>
#include <numbers>

#include "graph_batch.h"
#include "pattern_fields.h"

// Element-wise kernels: every operation is defined for every finite input (division by zero
// gives 0, the power of a negative number to a fractional exponent gives 0, and so on; the
// table is in docs/TEXTURES.md), so a graph's value is never NaN or infinite.
namespace soltex::graph {
namespace {

template <typename F>
void unary(const Program& program, const Instruction& instr, Batch& batch, F f) {
  const int comps = program.registers[static_cast<std::size_t>(instr.out)].components;
  for (int c = 0; c < comps; ++c) {
    const double* a = batch.operand(program, instr.in[0], c);
    double* out = batch.plane(instr.out, c);
    for (std::size_t i = 0; i < batch.size; ++i) out[i] = finite_or_zero(f(a[i]));
  }
}

template <typename F>
void binary(const Program& program, const Instruction& instr, Batch& batch, F f) {
  const int comps = program.registers[static_cast<std::size_t>(instr.out)].components;
  for (int c = 0; c < comps; ++c) {
    const double* a = batch.operand(program, instr.in[0], c);
    const double* b = batch.operand(program, instr.in[1], c);
    double* out = batch.plane(instr.out, c);
    for (std::size_t i = 0; i < batch.size; ++i) out[i] = finite_or_zero(f(a[i], b[i]));
  }
}

template <typename F>
void ternary(const Program& program, const Instruction& instr, Batch& batch, F f) {
  const int comps = program.registers[static_cast<std::size_t>(instr.out)].components;
  for (int c = 0; c < comps; ++c) {
    const double* a = batch.operand(program, instr.in[0], c);
    const double* b = batch.operand(program, instr.in[1], c);
    const double* d = batch.operand(program, instr.in[2], c);
    double* out = batch.plane(instr.out, c);
    for (std::size_t i = 0; i < batch.size; ++i) out[i] = finite_or_zero(f(a[i], b[i], d[i]));
  }
}

inline double smoothstep(double x, double low, double high) {
  if (!(low < high)) return x < low ? 0.0 : 1.0;  // a step where the interval is empty
  const double t = std::clamp((x - low) / (high - low), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

inline double remap(double x, double inlow, double inhigh, double outlow, double outhigh) {
  const double span = inhigh - inlow;
  if (span == 0.0) return outlow;
  return outlow + (x - inlow) * ((outhigh - outlow) / span);
}

void reduce(const Instruction& instr, Batch& batch) {
  double* out = batch.plane(instr.out, 0);
  const std::size_t n = batch.size;
  if (instr.op == Op::extract) {
    const double* a = batch.plane(instr.in[0], instr.index);
    for (std::size_t i = 0; i < n; ++i) out[i] = a[i];
    return;
  }
  const double *x = batch.plane(instr.in[0], 0), *y = batch.plane(instr.in[0], 1),
               *z = batch.plane(instr.in[0], 2);
  if (instr.op == Op::magnitude) {
    for (std::size_t i = 0; i < n; ++i) {
      const double xx = x[i] * x[i], yy = y[i] * y[i], zz = z[i] * z[i];
      out[i] = finite_or_zero(std::sqrt(xx + yy + zz));
    }
    return;
  }
  const double *u = batch.plane(instr.in[1], 0), *v = batch.plane(instr.in[1], 1),
               *w = batch.plane(instr.in[1], 2);
  for (std::size_t i = 0; i < n; ++i) {
    const double xu = x[i] * u[i], yv = y[i] * v[i], zw = z[i] * w[i];
    out[i] = finite_or_zero(xu + yv + zw);
  }
}

}  // namespace

void run_arithmetic(const Program& program, const Instruction& instr, Batch& batch) {
  switch (instr.op) {
    case Op::position:
    case Op::constant:
    case Op::convert:
      return unary(program, instr, batch, [](double a) { return a; });
    case Op::add:
      return binary(program, instr, batch, [](double a, double b) { return a + b; });
    case Op::subtract:
      return binary(program, instr, batch, [](double a, double b) { return a - b; });
    case Op::multiply:
      return binary(program, instr, batch, [](double a, double b) { return a * b; });
    case Op::divide:
      return binary(program, instr, batch,
                    [](double a, double b) { return b == 0.0 ? 0.0 : a / b; });
    case Op::modulo:
      return binary(program, instr, batch,
                    [](double a, double b) { return b == 0.0 ? 0.0 : a - b * std::floor(a / b); });
    case Op::power:
      return binary(program, instr, batch, [](double a, double b) { return std::pow(a, b); });
    case Op::min:
      return binary(program, instr, batch, [](double a, double b) { return b < a ? b : a; });
    case Op::max:
      return binary(program, instr, batch, [](double a, double b) { return a < b ? b : a; });
    case Op::abs:
      return unary(program, instr, batch, [](double a) { return std::fabs(a); });
    case Op::floor:
      return unary(program, instr, batch, [](double a) { return std::floor(a); });
    case Op::ceil:
      return unary(program, instr, batch, [](double a) { return std::ceil(a); });
    case Op::fract:
      return unary(program, instr, batch, [](double a) { return a - std::floor(a); });
    case Op::sin:
      return unary(program, instr, batch, [](double a) { return fields::portable_sin(a); });
    case Op::cos:
      return unary(program, instr, batch,
                   [](double a) { return fields::portable_sin(a + std::numbers::pi / 2.0); });
    case Op::sqrt:
      return unary(program, instr, batch, [](double a) { return a > 0.0 ? std::sqrt(a) : 0.0; });
    case Op::clamp:
      return ternary(program, instr, batch, [](double x, double low, double high) {
        const double lifted = x < low ? low : x;
        return high < lifted ? high : lifted;
      });
    case Op::smoothstep:
      return ternary(program, instr, batch, smoothstep);
    case Op::mix:
      return ternary(program, instr, batch, [](double fg, double bg, double m) {
        const double keep = bg * (1.0 - m);
        const double take = fg * m;
        return keep + take;
      });
    case Op::remap: {
      const int comps = program.registers[static_cast<std::size_t>(instr.out)].components;
      for (int c = 0; c < comps; ++c) {
        const double* in[5];
        for (int k = 0; k < 5; ++k) in[k] = batch.operand(program, instr.in[k], c);
        double* out = batch.plane(instr.out, c);
        for (std::size_t i = 0; i < batch.size; ++i) {
          out[i] = finite_or_zero(remap(in[0][i], in[1][i], in[2][i], in[3][i], in[4][i]));
        }
      }
      return;
    }
    case Op::combine3:
      for (int c = 0; c < 3; ++c) {
        const double* a = batch.plane(instr.in[c], 0);
        double* out = batch.plane(instr.out, c);
        for (std::size_t i = 0; i < batch.size; ++i) out[i] = a[i];
      }
      return;
    case Op::dotproduct:
    case Op::magnitude:
    case Op::extract:
      return reduce(instr, batch);
    default:
      return;
  }
}

}  // namespace soltex::graph
