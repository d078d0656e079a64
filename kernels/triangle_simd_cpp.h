// cpu dialect only: the robust watertight triangle test (intersect_triangle.h) on up to
// four triangles of a BVH leaf at once, one triangle per lane, with the GCC/Clang vector
// extensions. Every lane performs intersect_triangle's operations in the same order
// (the build compiles without contraction, -ffp-contract=off), its branches becoming
// lane masks, so each lane's crossing is bit-identical to the scalar call's. The ray's
// own values (dominant axis, shear, |d|) are computed once for the four, as the scalar
// call computes them, to the same bits.
//
// The scalar call takes a crossing when tt <= tmax * det: a scaled comparison, so
// whether it is taken is not decided by t = tt / det alone. The lanes therefore carry tt
// and det, and traverse_blas.h's take_triangle_lanes makes that comparison against the
// nearest hit of its turn, as the one-source loop would; everything else the call
// computes does not depend on tmax. Measured: docs/kernels.md, "Triangles in lanes".
#ifndef MASQ_KERNEL_TRIANGLE_SIMD_CPP_H
#define MASQ_KERNEL_TRIANGLE_SIMD_CPP_H
#if defined(MASQ_LANG_CPP)
#include "capsule_simd_cpp.h"
#include "intersect_triangle.h"

namespace masq::kernel::simd {

// Lane i: triangle i passed every test of the scalar call but the window's far end
// (hit != 0), with its scaled crossing tt and det > 0 (the call's tt <= tmax * det) and
// what the call returns for it.
struct TriangleHits4 {
  float tt[4], det[4];
  float t[4], u[4], v[4];
  float nx[4], ny[4], nz[4];
  int hit[4];
};

// Triangles tris[first + refs[j]], j < n, as four lanes (lanes n..3 repeat lane 0).
struct TriangleLanes4 {
  F4 x0, y0, z0, x1, y1, z1, x2, y2, z2;
};
inline TriangleLanes4 triangle_lanes4(const Triangle* tris, int first, const int* refs, int n) {
  TriangleLanes4 l;
  for (int i = 0; i < 4; ++i) {
    const Triangle& t = tris[first + refs[i < n ? i : 0]];
    l.x0[i] = t.v0[0];
    l.y0[i] = t.v0[1];
    l.z0[i] = t.v0[2];
    l.x1[i] = t.v1[0];
    l.y1[i] = t.v1[1];
    l.z1[i] = t.v1[2];
    l.x2[i] = t.v2[0];
    l.y2[i] = t.v2[1];
    l.z2[i] = t.v2[2];
  }
  return l;
}

// Component k (0, 1, 2: x, y, z) of a lane vector triple.
inline F4 pick(int k, F4 x, F4 y, F4 z) { return k == 0 ? x : (k == 1 ? y : z); }

// intersect_triangle on the lanes in `valid` against the ray (o, d) within [tmin, tmax].
inline TriangleHits4 triangle_hits4(const TriangleLanes4& c, I4 valid, glm::vec3 o, glm::vec3 d, float tmin,
                                    float tmax) {
  TriangleHits4 out;
  float dd = glm::dot(d, d);
  if (!(dd > 0.0f) || !(tmin <= tmax)) {
    for (int i = 0; i < 4; ++i) out.hit[i] = 0;
    return out;
  }
  // The ray's values, each as intersect_triangle computes it.
  float dl = std::sqrt(dd);
  glm::vec3 ad = glm::abs(d);
  int kz = (ad.x >= ad.y && ad.x >= ad.z) ? 0 : (ad.y >= ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  float dz = d[kz];
  if (dz < 0.0f) {
    int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  float sx = d[kx] / dz;
  float sy = d[ky] / dz;
  float sz = 1.0f / dz;
  // self_eps_t(0, o - v0, dd): (MASQ_SELF_REL * 0 + 32u (|o - v0| + 0)) / sqrt(dd).
  F4 ocx = o.x - c.x0, ocy = o.y - c.y0, ocz = o.z - c.z0;
  F4 loc = vsqrt(vdot(ocx, ocy, ocz, ocx, ocy, ocz));
  F4 eps = (splat(MASQ_SELF_REL * 0.0f) + (32.0f * MASQ_U) * (loc + 0.0f)) / dl;
  F4 tlo = tmin < eps ? eps : splat(tmin); // glm's max(tmin, eps)
  F4 ax3 = c.x0 - o.x, ay3 = c.y0 - o.y, az3 = c.z0 - o.z;
  F4 bx3 = c.x1 - o.x, by3 = c.y1 - o.y, bz3 = c.z1 - o.z;
  F4 cx3 = c.x2 - o.x, cy3 = c.y2 - o.y, cz3 = c.z2 - o.z;
  F4 akz = pick(kz, ax3, ay3, az3), bkz = pick(kz, bx3, by3, bz3), ckz = pick(kz, cx3, cy3, cz3);
  F4 ax = pick(kx, ax3, ay3, az3) - sx * akz;
  F4 ay = pick(ky, ax3, ay3, az3) - sy * akz;
  F4 bx = pick(kx, bx3, by3, bz3) - sx * bkz;
  F4 by = pick(ky, bx3, by3, bz3) - sy * bkz;
  F4 cx = pick(kx, cx3, cy3, cz3) - sx * ckz;
  F4 cy = pick(ky, cx3, cy3, cz3) - sy * ckz;
  F4 eu = cx * by - cy * bx;
  F4 ev = ax * cy - ay * cx;
  F4 ew = bx * ay - by * ax;
  I4 ok = valid & ~(((eu < 0.0f) | (ev < 0.0f) | (ew < 0.0f)) & ((eu > 0.0f) | (ev > 0.0f) | (ew > 0.0f)));
  F4 det = eu + ev + ew;
  ok = ok & (det != 0.0f);
  F4 az = sz * akz;
  F4 bz = sz * bkz;
  F4 cz = sz * ckz;
  F4 tt = eu * az + ev * bz + ew * cz;
  I4 flip = det < 0.0f;
  tt = flip ? -tt : tt;
  det = flip ? -det : det;
  ev = flip ? -ev : ev;
  ew = flip ? -ew : ew;
  // The far end here is the leaf's starting tmax: a lane beyond it is beyond every later
  // nearest hit too (fp multiplication is monotone), so the call misses it at its turn.
  ok = ok & (tt >= tlo * det) & (tt <= tmax * det);
  // intersect_triangle's plane rule, on the lanes still in.
  F4 e1x = c.x1 - c.x0, e1y = c.y1 - c.y0, e1z = c.z1 - c.z0;
  F4 e2x = c.x2 - c.x0, e2y = c.y2 - c.y0, e2z = c.z2 - c.z0;
  F4 nx = e1y * e2z - e2y * e1z; // glm's cross(e1, e2), term for term
  F4 ny = e1z * e2x - e2z * e1x;
  F4 nz = e1x * e2y - e2x * e1y;
  if (lane_bits(ok) != 0u) {
    F4 lv0 = vsqrt(vdot(c.x0, c.y0, c.z0, c.x0, c.y0, c.z0));
    F4 ln = vsqrt(vdot(nx, ny, nz, nx, ny, nz));
    F4 plane = vabs(vdot(ocx, ocy, ocz, nx, ny, nz));
    ok = ok & ~(plane <= (16.0f * MASQ_U) * (loc + lv0) * ln);
  }
  F4 inv_det = 1.0f / det;
  F4 t = tt * inv_det, u = ev * inv_det, v = ew * inv_det;
  for (int i = 0; i < 4; ++i) {
    out.hit[i] = ok[i] != 0 ? 1 : 0;
    out.tt[i] = tt[i];
    out.det[i] = det[i];
    out.t[i] = t[i];
    out.u[i] = u[i];
    out.v[i] = v[i];
    out.nx[i] = nx[i];
    out.ny[i] = ny[i];
    out.nz[i] = nz[i];
  }
  return out;
}

} // namespace masq::kernel::simd
#endif
#endif
