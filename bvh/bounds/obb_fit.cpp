#include "bvh/bounds/obb_fit.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace masq {

glm::dmat3 symmetric_eigenvectors(glm::dmat3 a) {
  glm::dmat3 v(1.0);
  for (int sweep = 0; sweep < 32; ++sweep) {
    double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off < 1e-30 * (a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2]) || off == 0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0) continue;
        double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        glm::dmat3 j(1.0);
        j[p][p] = c;
        j[q][q] = c;
        j[q][p] = s;  // column q, row p
        j[p][q] = -s; // column p, row q
        a = glm::transpose(j) * a * j;
        v = v * j;
      }
  }
  return v;
}

namespace {

// Orthonormal frame with first axis `e` and second axis as close as possible to `n`.
bool frame_from(glm::dvec3 e, glm::dvec3 n, glm::dmat3& out) {
  double le = glm::length(e);
  if (!(le > 0)) return false;
  e /= le;
  n -= glm::dot(n, e) * e;
  double ln = glm::length(n);
  if (!(ln > 1e-12)) {
    // Any perpendicular.
    n = std::fabs(e.x) < 0.9 ? glm::cross(e, glm::dvec3(1, 0, 0)) : glm::cross(e, glm::dvec3(0, 1, 0));
    ln = glm::length(n);
  }
  n /= ln;
  out = glm::dmat3(e, n, glm::cross(e, n));
  return true;
}

const std::array<glm::dvec3, 7> kObbDirs = {glm::dvec3{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1},
                                         {1, 1, -1},          {1, -1, 1}, {1, -1, -1}};

// The extents of the hulls along each of axes[0..n) (not necessarily unit: a ball of
// radius r reaches r |axis|) in one pass over the balls, each axis's minimum and maximum
// taken in ball order: a set of hulls larger than the cache is read once, not once an
// axis.
template <std::size_t N>
void hull_extents(std::span<const BallHull> hulls, const std::array<glm::dvec3, N>& axes, std::size_t n,
                  std::array<Interval, N>& out) {
  std::array<double, N> len{};
  for (std::size_t a = 0; a < n; ++a) len[a] = glm::length(axes[a]), out[a] = Interval{};
  for (const BallHull& h : hulls)
    for (int i = 0; i < h.count; ++i)
      for (std::size_t a = 0; a < n; ++a) {
        double s = glm::dot(axes[a], h.centre[i]);
        out[a].lo = std::min(out[a].lo, s - h.radius[i] * len[a]);
        out[a].hi = std::max(out[a].hi, s + h.radius[i] * len[a]);
      }
}

// The box in the frame `axes` (columns) of the extents along them; empty (ObbFrame{})
// when any is.
ObbFrame obb_from_extents(const glm::dmat3& axes, const Interval* extent) {
  ObbFrame f;
  f.axes = axes;
  glm::dvec3 mid{0.0};
  for (int k = 0; k < 3; ++k) {
    const Interval& iv = extent[k];
    if (!(iv.lo <= iv.hi)) return ObbFrame{};
    mid[k] = 0.5 * (iv.lo + iv.hi);
    f.half[k] = 0.5 * (iv.hi - iv.lo);
  }
  f.centre = axes * mid;
  return f;
}

} // namespace

Interval hull_extent(std::span<const BallHull> hulls, const glm::dvec3& axis) {
  std::array<Interval, 1> iv;
  hull_extents(hulls, std::array<glm::dvec3, 1>{axis}, 1, iv);
  return iv[0];
}

ObbFrame obb_in_frame(std::span<const BallHull> hulls, const glm::dmat3& axes) {
  std::array<Interval, 3> iv;
  hull_extents(hulls, std::array<glm::dvec3, 3>{axes[0], axes[1], axes[2]}, 3, iv);
  return obb_from_extents(axes, iv.data());
}

ObbFrame fit_obb(std::span<const BallHull> hulls) {
  std::vector<glm::dmat3> candidates = {glm::dmat3(1.0)};
  // One pass: the mean of the ball centres, and (DiTO) the extremal centres along 7
  // directions.
  glm::dvec3 mean{0.0};
  std::size_t n = 0;
  std::array<double, kObbDirs.size()> lo, hi;
  std::array<glm::dvec3, kObbDirs.size()> plo, phi;
  lo.fill(INFINITY), hi.fill(-INFINITY), plo.fill(glm::dvec3{0.0}), phi.fill(glm::dvec3{0.0});
  for (const BallHull& h : hulls)
    for (int i = 0; i < h.count; ++i) {
      mean += h.centre[i], ++n;
      for (std::size_t d = 0; d < kObbDirs.size(); ++d) {
        double s = glm::dot(kObbDirs[d], h.centre[i]);
        if (s < lo[d]) lo[d] = s, plo[d] = h.centre[i];
        if (s > hi[d]) hi[d] = s, phi[d] = h.centre[i];
      }
    }
  if (n == 0) return ObbFrame{};
  mean /= double(n);
  // Principal axes of the ball centres.
  glm::dmat3 cov(0.0);
  for (const BallHull& h : hulls)
    for (int i = 0; i < h.count; ++i) {
      glm::dvec3 d = h.centre[i] - mean;
      cov += glm::outerProduct(d, d);
    }
  candidates.push_back(symmetric_eigenvectors(cov));
  // DiTO: the farthest pair of extremal centres and the point farthest from its line
  // span a triangle whose edges (with its normal) give three frames.
  std::vector<glm::dvec3> ext;
  for (std::size_t d = 0; d < kObbDirs.size(); ++d) {
    ext.push_back(plo[d]);
    ext.push_back(phi[d]);
  }
  std::size_t a = 0, b = 0;
  double best = -1;
  for (std::size_t i = 0; i < ext.size(); ++i)
    for (std::size_t j = i + 1; j < ext.size(); ++j) {
      double d2 = glm::dot(ext[i] - ext[j], ext[i] - ext[j]);
      if (d2 > best) best = d2, a = i, b = j;
    }
  glm::dvec3 e0 = ext[b] - ext[a];
  if (best > 0) {
    glm::dvec3 u = glm::normalize(e0);
    std::size_t c = a;
    double far = -1;
    for (std::size_t i = 0; i < ext.size(); ++i) {
      glm::dvec3 w = ext[i] - ext[a];
      double d2 = glm::dot(w, w) - glm::dot(w, u) * glm::dot(w, u);
      if (d2 > far) far = d2, c = i;
    }
    glm::dvec3 nrm = glm::cross(e0, ext[c] - ext[a]);
    glm::dmat3 f;
    for (glm::dvec3 e : {e0, ext[c] - ext[b], ext[a] - ext[c]})
      if (frame_from(e, glm::length(nrm) > 0 ? glm::cross(nrm, e) : glm::dvec3(0.0), f)) candidates.push_back(f);
  }
  // Every candidate's box (obb_in_frame's), their 3 axes each in one pass; the least
  // area wins, the earlier candidate on a tie.
  constexpr std::size_t kMaxAxes = 3 * 5; // identity, PCA and up to three DiTO frames
  std::array<glm::dvec3, kMaxAxes> axes{};
  std::array<Interval, kMaxAxes> extent{};
  for (std::size_t k = 0; k < candidates.size(); ++k)
    for (int j = 0; j < 3; ++j) axes[3 * k + std::size_t(j)] = candidates[k][j];
  hull_extents(hulls, axes, 3 * candidates.size(), extent);
  ObbFrame out;
  double area = INFINITY;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    ObbFrame f = obb_from_extents(candidates[k], extent.data() + 3 * k);
    if (f.area() < area) area = f.area(), out = f;
  }
  return out;
}

} // namespace masq
