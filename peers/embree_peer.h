// Embree 3 as a peer tracer: the benchmark harness traces the same rays through masq and
// through Embree (rtcIntersect1 per ray or its stream API, on oneTBB's workers) and compares time, memory
// and answers. No Embree header here (pimpl), so callers build whether or not masq was
// built with Embree; without it every constructor throws and unavailable_reason() says why.
//
// Mapping (one Embree geometry per masq Geometry, in its own sub-scene committed once and
// shared by every instance of it; one RTC_GEOMETRY_TYPE_INSTANCE per masq Instance, its
// object_to_world rounded to a 3x4 float transform):
//   capsule    -> round linear curve, radius at both vertices, no neighbours (flags 0)
//   round cone -> round linear curve with per-vertex radii (Embree's segment is the
//                 convex hull of its two end balls, as masq's round cone)
//   curve      -> round Bezier curve, the same four control points (Bezier basis in both)
//                 and the curve's radius at each; Embree 3's cubic round curves are open
//                 tubes, masq's are closed by the end balls, so by default (CurveEnds) a
//                 second geometry of sphere points closes every end no neighbour covers
//   sphere     -> sphere point
//   triangle   -> triangle
#pragma once
#include "kernels/layout.h"
#include "scenes/scene.h"
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace masq {

// What closes the ends of round Bezier curves. Embree 3 sweeps a circle along a cubic
// (RTC_GEOMETRY_TYPE_CURVE(3), "Round Curves"; its neighbour flags are for the linear
// basis only), so each cubic is a tube open at both ends; masq's curve is the union of
// the balls B(C(s), r), closed by the balls at s = 0 and 1. Sphere points of radius r at
// the ends give Embree masq's shape: the union of balls along a C1 curve is the union
// of its normal disks (what the tube bounds) and its two end balls.
enum class CurveEnds {
  Open,       // Embree's curves alone: open tubes
  StrandEnds, // a sphere at every curve end that no neighbour covers (masq's shape)
  EveryEnd,   // a sphere at both ends of every curve (the same shape, more spheres)
};

// An end is covered when the neighbouring curve of the same geometry (index i-1 before
// the start, i+1 after the end) starts or ends at exactly that point, continues with the
// same tangent direction (within 1e-3 rad) and has a radius at least as large: the ball
// there then lies in the union of the two tubes' disks.
bool curve_end_covered(const std::vector<CurvePrim>& curves, std::size_t i, int end);

// How the peer hands rays to Embree. PerRay: rtcIntersect1 / rtcOccluded1 for each ray;
// Stream: rtcIntersect1M / rtcOccluded1M on each chunk of the batch (Embree's stream
// API, for callers that trace batches, as masq does), with the coherent-rays hint when
// `coherent` (camera rays) and Embree's default (incoherent) otherwise.
enum class EmbreeApi { PerRay, Stream };
struct EmbreeTrace {
  EmbreeApi api = EmbreeApi::PerRay;
  bool coherent = false;
};
const char* embree_api_name(EmbreeApi api); // "rtcIntersect1", "rtcIntersect1M"

struct PeerTiming {
  double build_seconds = 0; // last set_scene: geometry upload and every BVH build
  double trace_seconds = 0; // last trace: wall time of the whole batch
};

class EmbreePeer {
 public:
  // "" when masq was built with Embree 3, else the one-line reason it was not.
  static std::string unavailable_reason();
  static std::string version(); // "Embree 3.13.5" (the headers masq was built against)

  // threads: how many threads trace (chunks of the batch in a oneTBB arena) and build
  // (Embree's device is limited to as many), at most the hardware's; oneTBB's workers,
  // shared with Embree and the masq cpu backend. Throws masq::Error when built without
  // Embree or when Embree cannot make a device.
  explicit EmbreePeer(int threads = 2);
  ~EmbreePeer();
  EmbreePeer(const EmbreePeer&) = delete;
  EmbreePeer& operator=(const EmbreePeer&) = delete;

  // Builds Embree's BVHs for the scene (replacing any previous one). robust ->
  // RTC_SCENE_FLAG_ROBUST on every scene. Throws masq::Error for invalid scenes and for
  // any Embree error (with Embree's message). A scene with no instances or no
  // primitives is allowed: every ray misses. ends: how curves are closed (above); a hit
  // on an end sphere is reported as the curve it closes (u = 0 or 1).
  void set_scene(const Scene& scene, bool robust, CurveEnds ends = CurveEnds::StrandEnds);

  // Closest hit of each ray (hits.size() >= rays.size()), masq's conventions:
  // miss: t = +inf, prim = geom = inst = -1, normal and u, v zero. Hit: t in units of
  // ray.dir, prim/geom/inst the masq indices, normal the unit world-space geometric
  // normal (Embree's Ng), u, v as kernel::Hit documents (triangles: Embree's
  // barycentrics; capsules, round cones, curves: Embree's u, v = 0; spheres: 0, 0).
  // Invalid rays (non-finite, zero direction, tmin > tmax) miss without reaching Embree.
  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits, EmbreeTrace how = {});

  // Occlusion (shadow rays): occluded[i] = 1 when any surface lies in [tmin, tmax]
  // (rtcOccluded1 or rtcOccluded1M, which stop at the first hit found). Invalid rays are
  // unoccluded.
  void occluded(std::span<const kernel::Ray> rays, std::span<std::uint8_t> occluded, EmbreeTrace how = {});

  PeerTiming timing() const;
  // Bytes Embree holds for the current scene (its memory monitor after the build:
  // vertex/index buffers and BVHs).
  std::size_t bytes() const;
  // Sphere points the current scene's curves got (CurveEnds), over all geometries.
  std::size_t end_spheres() const;
  // "Embree 3.13.5, 2 threads, RTC_SCENE_FLAG_ROBUST, build quality medium (Embree's
  // default), round linear curves/round Bezier curves/triangles" (the Embree types of the current scene; end spheres of curves
  // as "round Bezier curves + end spheres").
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace masq
