// The quadratic and polynomial root finders of solve.h.
#include "oracle/solve.h"

namespace masq::oracle::detail {

int quadratic(ld A, ld B, ld C, ld out[2]) {
  if (A == 0) {
    if (B == 0) return 0;
    out[0] = -C / (2 * B);
    return 1;
  }
  ld disc = B * B - A * C;
  if (disc < 0) return 0;
  ld q = -(B + std::copysign(std::sqrt(disc), B));
  if (q == 0) { // B = 0 and A C = 0, so C = 0
    out[0] = 0;
    return 1;
  }
  out[0] = q / A;
  out[1] = C / q;
  return 2;
}

Roots poly_roots(const ld* p, int n, ld lo, ld hi) {
  Roots out;
  while (n > 0 && p[n] == 0) --n;
  if (n <= 0) return out;
  if (n == 1) {
    ld x = -p[0] / p[1];
    if (x > lo && x < hi) out.push(x);
    return out;
  }
  ld dp[8];
  for (int i = 0; i < n; ++i) dp[i] = ld(i + 1) * p[i + 1];
  Roots cr = poly_roots(dp, n - 1, lo, hi);
  ld nodes[10];
  int nn = 0;
  nodes[nn++] = lo;
  for (int i = 0; i < cr.n; ++i) nodes[nn++] = cr.r[i];
  nodes[nn++] = hi;
  ld v0 = peval(p, n, lo);
  for (int k = 0; k + 1 < nn; ++k) {
    ld v1 = peval(p, n, nodes[k + 1]);
    if (v0 == 0 && k > 0) {
      out.push(nodes[k]);
    } else if ((v0 < 0 && v1 > 0) || (v0 > 0 && v1 < 0)) {
      auto fn = [&](ld x) { return std::pair{peval(p, n, x), peval(dp, n - 1, x)}; };
      out.push(solve_bracketed(fn, nodes[k], nodes[k + 1], v0));
    }
    v0 = v1;
  }
  return out;
}

} // namespace masq::oracle::detail
