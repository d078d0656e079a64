// One-variable solvers in long double for the primitives' oracles: the quadratic's
// cancellation-free roots (every round primitive), and the polynomial roots and
// unimodal minima on [0, 1] the curve's swept-sphere solve needs. Internal to oracle/.
#pragma once
#include "oracle/oracle_prims.h"
#include <cmath>
#include <limits>
#include <utility>

namespace masq::oracle::detail {

// Real roots of A x^2 + 2 B x + C = 0 (any A), without cancellation between -B and the
// root of the discriminant.
int quadratic(ld A, ld B, ld C, ld out[2]);

// The polynomial p[0] + p[1] x + ... + p[n] x^n at x (Horner).
inline ld peval(const ld* p, int n, ld x) {
  ld v = p[n];
  for (int i = n - 1; i >= 0; --i) v = v * x + p[i];
  return v;
}

struct Roots {
  ld r[8];
  int n = 0;
  void push(ld x) {
    if (n < 8) r[n++] = x;
  }
};

// Root of fn in [a, b] where fn changes sign (fa: the value at a); fn(x) returns
// {value, derivative}. Newton steps, replaced by bisection whenever they leave the
// bracket, until the step or the bracket reaches long-double resolution.
template <class Fn>
ld solve_bracketed(Fn fn, ld a, ld b, ld fa) {
  ld x = 0.5L * (a + b);
  for (int it = 0; it < 160; ++it) {
    auto [fx, dfx] = fn(x);
    if (fx == 0) return x;
    if ((fx < 0) == (fa < 0)) {
      a = x;
      fa = fx;
    } else {
      b = x;
    }
    ld xn = x - fx / dfx;
    if (!(xn > a && xn < b) || it % 8 == 7) xn = 0.5L * (a + b); // periodic bisection bounds the count
    if (xn <= a || xn >= b) return x;
    if (std::fabs(xn - x) <= 4 * std::numeric_limits<ld>::epsilon() * std::fabs(x)) return xn;
    x = xn;
  }
  return x;
}

// Every root of the degree-n polynomial p in (lo, hi), ascending: the derivative's roots
// split [lo, hi] into pieces on which p is monotone, so each sign change is one root.
Roots poly_roots(const ld* p, int n, ld lo, ld hi);

// Minimum of a unimodal function over [lo, hi] by golden section: (argmin, min).
template <class Fn>
std::pair<ld, ld> golden_min(Fn fn, ld lo, ld hi, ld rel_width) {
  const ld g = 0.6180339887498948482045868343656381L;
  ld w0 = hi - lo;
  ld x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = fn(x1), f2 = fn(x2);
  for (int it = 0; it < 200 && hi - lo > rel_width * w0; ++it) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = fn(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = fn(x2);
    }
  }
  return f1 <= f2 ? std::pair{x1, f1} : std::pair{x2, f2};
}

} // namespace masq::oracle::detail
