// Embree 3 peer: device, errors, memory accounting, scene mapping and threaded tracing.
// Embree semantics that matter for the comparison (3.13.5, measured against the
// long-double oracle in tests/test_embree_peer.cpp):
//  - Round linear curve segments take their neighbours from RTC_BUFFER_TYPE_FLAGS; with
//    a neighbour, the parts of a segment's end ball inside the neighbouring cone are cut
//    away. Capsules and round cones are independent, so each segment indexes its own two
//    vertices (index 2*i) and the flags are set explicitly to 0, not left to Embree:
//    both end balls are whole and the segment is the convex hull of its two balls,
//    masq's capsule / round cone, also when one ball contains the other (Embree then
//    reports that ball alone; 100% agreement on the generator's contained round cones).
//  - Round Bezier curves are open tubes: Embree's sweep has no end balls, so rays that
//    hit masq's round curve ends miss, or enter the open end and hit the inside wall.
//    Away from the ends the surfaces agree. Sphere points close the ends (CurveEnds in
//    embree_peer.h); they live in the curve's sub-scene as geometry 1.
//  - For hits inside instances, Ng comes back in the instance's object space.
#include "peers/embree_peer.h"
#include "masq/error.h"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#if MASQ_HAVE_EMBREE
#include <embree3/rtcore.h>
#include <atomic>
#include <mutex>
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#endif

namespace masq {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

kernel::Hit miss_hit() {
  kernel::Hit h{};
  h.t = std::numeric_limits<float>::infinity();
  h.prim = -1;
  h.geom = -1;
  h.inst = -1;
  return h;
}

// Same rule as the kernels' ray_is_valid (kernels/traverse.h).
bool ray_valid(const kernel::Ray& r) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(r.org[k]) || !std::isfinite(r.dir[k])) return false;
  float dd = r.dir[0] * r.dir[0] + r.dir[1] * r.dir[1] + r.dir[2] * r.dir[2];
  return dd > 0.0f && !std::isnan(r.tmin) && !std::isnan(r.tmax) && r.tmin <= r.tmax;
}

} // namespace

bool curve_end_covered(const std::vector<CurvePrim>& curves, std::size_t i, int end) {
  const CurvePrim& c = curves[i];
  std::size_t j = end == 0 ? i - 1 : i + 1; // the neighbour (wraps for i = 0: caught below)
  if (j >= curves.size()) return false;
  const CurvePrim& o = curves[j];
  // This curve's end point and its tangent pointing along the strand, and the
  // neighbour's, both in the same direction when the two continue each other.
  glm::vec3 p = end == 0 ? c.p[0] : c.p[3], q = end == 0 ? o.p[3] : o.p[0];
  if (p != q || o.radius < c.radius) return false;
  glm::dvec3 a = end == 0 ? glm::dvec3(c.p[1]) - glm::dvec3(c.p[0]) : glm::dvec3(c.p[3]) - glm::dvec3(c.p[2]);
  glm::dvec3 b = end == 0 ? glm::dvec3(o.p[3]) - glm::dvec3(o.p[2]) : glm::dvec3(o.p[1]) - glm::dvec3(o.p[0]);
  double la = glm::length(a), lb = glm::length(b);
  if (!(la > 0.0 && lb > 0.0)) return false;
  return glm::dot(a, b) > 0.0 && glm::length(glm::cross(a, b)) <= 1e-3 * la * lb;
}

std::string EmbreePeer::version() {
#if MASQ_HAVE_EMBREE
  return std::string("Embree ") + RTC_VERSION_STRING;
#else
  return "Embree (not built)";
#endif
}

std::string EmbreePeer::unavailable_reason() {
#if MASQ_HAVE_EMBREE
  return "";
#else
  return "embree: masq was built without Embree 3 (install libembree-dev and rebuild)";
#endif
}

#if MASQ_HAVE_EMBREE

namespace {

const char* rtc_error_name(RTCError e) {
  static const char* const names[] = {"RTC_ERROR_NONE",          "RTC_ERROR_UNKNOWN",
                                      "RTC_ERROR_INVALID_ARGUMENT", "RTC_ERROR_INVALID_OPERATION",
                                      "RTC_ERROR_OUT_OF_MEMORY", "RTC_ERROR_UNSUPPORTED_CPU",
                                      "RTC_ERROR_CANCELLED"};
  return unsigned(e) < 7 ? names[unsigned(e)] : "RTC_ERROR_?";
}

} // namespace

struct EmbreePeer::Impl {
  // Embree 3 runs on oneTBB (Debian's libembree3 links libtbb), so the traces below, in
  // an arena of `threads`, and Embree's BVH builds, which its device holds to as many
  // (a process-wide tbb::global_control of Embree's), run on oneTBB's workers: started
  // once for the process, and the ones the masq cpu backend traces on
  // (host/cpu/trace_threads.h). At most the hardware's threads: oneTBB gives no more.
  explicit Impl(int requested)
      : threads(std::clamp(requested, 1, tbb::info::default_concurrency())), arena(threads) {}
  int threads;
  tbb::task_arena arena;
  bool robust = false;
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  std::vector<RTCScene> subs;        // one per masq geometry
  std::vector<int> inst_geom;        // masq instance -> masq geometry
  std::vector<glm::dmat3> inst_nrm;  // masq instance -> inverse transpose of its linear part
  std::vector<PrimType> geom_type;   // masq geometry -> type
  std::vector<std::vector<int>> caps; // masq geometry -> its end spheres' 2 * curve + end
  CurveEnds ends = CurveEnds::StrandEnds;
  std::size_t end_spheres = 0;
  std::atomic<long long> live_bytes{0};
  std::size_t scene_bytes = 0;
  PeerTiming timing;
  std::mutex error_mutex;
  std::string error_message; // first Embree error since the last check

  // Embree reports errors through this callback (which must not throw through Embree's
  // C frames); check() turns a recorded error into a masq::Error.
  static void on_error(void* user, RTCError code, const char* str) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard<std::mutex> lock(self->error_mutex);
    if (self->error_message.empty())
      self->error_message = std::string(rtc_error_name(code)) + (str != nullptr ? std::string(": ") + str : "");
  }
  static bool on_memory(void* user, ssize_t bytes, bool /*post*/) {
    static_cast<Impl*>(user)->live_bytes += bytes;
    return true;
  }
  void check(const char* what) {
    RTCError code = rtcGetDeviceError(device);
    std::string msg;
    {
      std::lock_guard<std::mutex> lock(error_mutex);
      msg.swap(error_message);
    }
    if (code == RTC_ERROR_NONE && msg.empty()) return;
    if (msg.empty()) msg = rtc_error_name(code);
    throw Error(std::string("embree: ") + what + ": " + msg);
  }
  void release_scene() {
    if (top != nullptr) rtcReleaseScene(top);
    top = nullptr;
    for (RTCScene s : subs) rtcReleaseScene(s);
    subs.clear();
    inst_geom.clear();
    inst_nrm.clear();
    geom_type.clear();
    caps.clear();
    end_spheres = 0;
  }
  RTCGeometry make_geometry(const Geometry& g);
  RTCGeometry make_end_caps(const Geometry& g, std::vector<int>& owner);
  // A hit of Embree's in masq's conventions (EmbreePeer::trace).
  void to_hit(const RTCRayHit& rh, kernel::Hit& h) const;
  // fn(begin, end) over [0, n) in chunks of at most 256 rays on the arena's threads;
  // each ray is traced alone into its own slot, so the split cannot change an answer.
  template <class Fn>
  void for_chunks(std::size_t n, Fn fn) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256),
                        [&](const tbb::blocked_range<std::size_t>& r) { fn(r.begin(), r.end()); });
    });
  }
};

namespace {

// count elements of `per` values of T each (float4 vertices: T = float, per = 4).
template <class T>
T* new_buffer(RTCGeometry geo, RTCBufferType type, RTCFormat format, std::size_t count, std::size_t per = 1) {
  void* p = rtcSetNewGeometryBuffer(geo, type, 0, format, per * sizeof(T), count);
  return static_cast<T*>(p);
}

void put4(float* dst, const glm::vec3& p, float r) {
  dst[0] = p.x;
  dst[1] = p.y;
  dst[2] = p.z;
  dst[3] = r;
}

// Round linear curve of independent two-vertex segments (capsules and round cones).
RTCGeometry make_segments(RTCDevice device, std::size_t n, auto&& vertex_pair) {
  RTCGeometry geo = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
  float* v = new_buffer<float>(geo, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4, 2 * n, 4);
  unsigned* idx = new_buffer<unsigned>(geo, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT, n);
  unsigned char* flags = new_buffer<unsigned char>(geo, RTC_BUFFER_TYPE_FLAGS, RTC_FORMAT_UCHAR, n);
  if (v == nullptr || idx == nullptr || flags == nullptr) return geo; // the error is recorded
  for (std::size_t i = 0; i < n; ++i) {
    vertex_pair(i, v + 8 * i, v + 8 * i + 4);
    idx[i] = unsigned(2 * i);
    flags[i] = 0; // no neighbours: both end balls whole
  }
  return geo;
}

RTCGeometry make_capsules(RTCDevice device, const Geometry& g) {
  return make_segments(device, g.capsules.size(), [&](std::size_t i, float* a, float* b) {
    put4(a, g.capsules[i].a, g.capsules[i].radius);
    put4(b, g.capsules[i].b, g.capsules[i].radius);
  });
}
RTCGeometry make_round_cones(RTCDevice device, const Geometry& g) {
  return make_segments(device, g.round_cones.size(), [&](std::size_t i, float* a, float* b) {
    put4(a, g.round_cones[i].a, g.round_cones[i].ra);
    put4(b, g.round_cones[i].b, g.round_cones[i].rb);
  });
}
RTCGeometry make_curves(RTCDevice device, const Geometry& g) {
  std::size_t n = g.curves.size();
  RTCGeometry geo = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE);
  float* v = new_buffer<float>(geo, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4, 4 * n, 4);
  unsigned* idx = new_buffer<unsigned>(geo, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT, n);
  if (v == nullptr || idx == nullptr) return geo;
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 4; ++k) put4(v + 16 * i + 4 * k, g.curves[i].p[std::size_t(k)], g.curves[i].radius);
    idx[i] = unsigned(4 * i);
  }
  return geo;
}
RTCGeometry make_spheres(RTCDevice device, const Geometry& g) {
  std::size_t n = g.spheres.size();
  RTCGeometry geo = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  float* v = new_buffer<float>(geo, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4, n, 4);
  if (v == nullptr) return geo;
  for (std::size_t i = 0; i < n; ++i) put4(v + 4 * i, g.spheres[i].center, g.spheres[i].radius);
  return geo;
}
RTCGeometry make_triangles(RTCDevice device, const Geometry& g) {
  RTCGeometry geo = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* v = new_buffer<float>(geo, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, g.vertices.size(), 3);
  unsigned* idx = new_buffer<unsigned>(geo, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT3, g.triangles.size(), 3);
  if (v == nullptr || idx == nullptr) return geo;
  for (std::size_t i = 0; i < g.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + std::size_t(k)] = g.vertices[i][k];
  for (std::size_t i = 0; i < g.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) idx[3 * i + std::size_t(k)] = g.triangles[i][k];
  return geo;
}

// Embree 3's flat linear curves face the ray, not a normal, and its normal-oriented
// curves have no linear basis; a linear ribbon is a planar trapezoid, so its peer is one
// Embree quad per ribbon (corners p0 +/- r0 w, p1 -/+ r1 w, w the unit width direction,
// in double, rounded to fp32): the same surface, primID the ribbon's index. Its (u, v)
// are the quad's, not the ribbon's, so the peer reports none.
RTCGeometry make_ribbons(RTCDevice device, const Geometry& g) {
  RTCGeometry geo = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_QUAD);
  const std::size_t n = g.ribbons.size();
  float* v = new_buffer<float>(geo, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, 4 * n, 3);
  unsigned* idx = new_buffer<unsigned>(geo, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT4, n, 4);
  if (v == nullptr || idx == nullptr) return geo;
  for (std::size_t i = 0; i < n; ++i) {
    const RibbonPrim& r = g.ribbons[i];
    const glm::dvec3 p0(r.p0), p1(r.p1);
    glm::dvec3 w = glm::cross(glm::dvec3(r.n), p1 - p0);
    const double wl = glm::length(w), nl = glm::length(glm::dvec3(r.n)) * glm::length(p1 - p0);
    // masq's rule (kernels/intersect_ribbon.h): a normal within 2^-12 rad of the axis has
    // no width direction; then a quad without area, never hit.
    w = wl > 0x1p-12 * nl ? w / wl : glm::dvec3(0.0);
    // Wound so that Embree's Ng (its triangles (v0, v1, v3) and (v2, v3, v1): (v1 - v0) x
    // (v3 - v0), a multiple of (p1 - p0) x w) faces n, as masq's ribbon normal does.
    const glm::dvec3 corner[4] = {p0 + double(r.r0) * w, p0 - double(r.r0) * w, p1 - double(r.r1) * w,
                                  p1 + double(r.r1) * w};
    for (std::size_t k = 0; k < 4; ++k) {
      for (int c = 0; c < 3; ++c) v[3 * (4 * i + k) + std::size_t(c)] = float(corner[k][c]);
      idx[4 * i + k] = unsigned(4 * i + k);
    }
  }
  return geo;
}

// Embree's geometry kinds, in the order description() lists them.
enum class EmbreeKind { Linear, Bezier, Spheres, Triangles };
// What a hit's (u, v) holds: the barycentrics, nothing, or the curve parameter (an end
// cap's: the end, 0 or 1).
enum class HitUv { Barycentric, None, CurveParameter };

// The peer's table of primitive types: Embree's geometry for each, row i for PrimType(i).
struct EmbreePrimRow {
  PrimType type;
  EmbreeKind kind;
  HitUv uv;
  RTCGeometry (*make)(RTCDevice, const Geometry&);
};
constexpr EmbreePrimRow embree_prim_rows[] = {
    {PrimType::Triangle, EmbreeKind::Triangles, HitUv::Barycentric, make_triangles},
    {PrimType::Capsule, EmbreeKind::Linear, HitUv::CurveParameter, make_capsules},
    {PrimType::RoundCone, EmbreeKind::Linear, HitUv::CurveParameter, make_round_cones},
    {PrimType::Sphere, EmbreeKind::Spheres, HitUv::None, make_spheres},
    {PrimType::Curve, EmbreeKind::Bezier, HitUv::CurveParameter, make_curves},
    {PrimType::Ribbon, EmbreeKind::Triangles, HitUv::None, make_ribbons}, // a quad: Embree's triangle family
};
static_assert(one_row_per_prim_type(embree_prim_rows), "embree prim rows: one row per PrimType, in enum order");

const EmbreePrimRow& embree_prim_row(PrimType t) {
  const auto i = static_cast<std::size_t>(t);
  if (i >= prim_type_count) throw Error("embree: unknown primitive type");
  return embree_prim_rows[i];
}

} // namespace

RTCGeometry EmbreePeer::Impl::make_geometry(const Geometry& g) { return embree_prim_row(g.type).make(device, g); }

// Sphere points closing a curve geometry's ends (CurveEnds); owner[k] = 2 * curve + end
// of sphere k. nullptr when there are none.
RTCGeometry EmbreePeer::Impl::make_end_caps(const Geometry& g, std::vector<int>& owner) {
  owner.clear();
  if (embree_prim_row(g.type).kind != EmbreeKind::Bezier || ends == CurveEnds::Open) return nullptr;
  for (std::size_t i = 0; i < g.curves.size(); ++i)
    for (int e = 0; e < 2; ++e)
      if (ends == CurveEnds::EveryEnd || !curve_end_covered(g.curves, i, e)) owner.push_back(int(2 * i) + e);
  if (owner.empty()) return nullptr;
  RTCGeometry geo = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  float* v = new_buffer<float>(geo, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4, owner.size(), 4);
  if (v == nullptr) return geo;
  for (std::size_t k = 0; k < owner.size(); ++k) {
    const CurvePrim& c = g.curves[std::size_t(owner[k] / 2)];
    put4(v + 4 * k, owner[k] % 2 == 0 ? c.p[0] : c.p[3], c.radius);
  }
  return geo;
}

EmbreePeer::EmbreePeer(int threads) {
  if (threads < 1) throw Error("embree: thread count must be at least 1 (got " + std::to_string(threads) + ")");
  impl_ = std::make_unique<Impl>(threads);
  std::string config = "threads=" + std::to_string(impl_->threads);
  impl_->device = rtcNewDevice(config.c_str());
  if (impl_->device == nullptr)
    throw Error(std::string("embree: rtcNewDevice failed: ") + rtc_error_name(rtcGetDeviceError(nullptr)));
  rtcSetDeviceErrorFunction(impl_->device, &Impl::on_error, impl_.get());
  rtcSetDeviceMemoryMonitorFunction(impl_->device, &Impl::on_memory, impl_.get());
}

EmbreePeer::~EmbreePeer() {
  impl_->release_scene();
  rtcReleaseDevice(impl_->device);
}

void EmbreePeer::set_scene(const Scene& scene, bool robust, CurveEnds ends) {
  Impl& m = *impl_;
  bool empty = scene.instances.empty() || scene.primitive_count() == 0;
  if (!empty) validate_scene(scene);
  m.release_scene();
  m.robust = robust;
  m.ends = ends;
  m.check("before set_scene");
  auto t0 = std::chrono::steady_clock::now();
  RTCSceneFlags flags = robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE;
  try {
    for (std::size_t gi = 0; gi < scene.geometries.size(); ++gi) {
      const Geometry& g = scene.geometries[gi];
      m.geom_type.push_back(g.type);
      m.caps.emplace_back();
      RTCScene sub = rtcNewScene(m.device);
      m.subs.push_back(sub);
      rtcSetSceneFlags(sub, flags);
      if (!empty && g.primitive_count() > 0) {
        RTCGeometry geo = m.make_geometry(g);
        rtcCommitGeometry(geo);
        rtcAttachGeometryByID(sub, geo, 0);
        rtcReleaseGeometry(geo);
        if (RTCGeometry caps = m.make_end_caps(g, m.caps.back())) {
          rtcCommitGeometry(caps);
          rtcAttachGeometryByID(sub, caps, 1);
          rtcReleaseGeometry(caps);
          m.end_spheres += m.caps.back().size();
        }
      }
      rtcCommitScene(sub);
      m.check(("building geometry " + std::to_string(gi)).c_str());
    }
    m.top = rtcNewScene(m.device);
    rtcSetSceneFlags(m.top, flags);
    if (!empty) {
      for (std::size_t ii = 0; ii < scene.instances.size(); ++ii) {
        const Instance& in = scene.instances[ii];
        const Affine3& x = in.object_to_world;
        float xfm[12];
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) xfm[4 * r + c] = float(x.linear[c][r]); // glm: [column][row]
          xfm[4 * r + 3] = float(x.translation[r]);
        }
        RTCGeometry ig = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(ig, m.subs[in.geometry]);
        rtcSetGeometryTransform(ig, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
        rtcCommitGeometry(ig);
        rtcAttachGeometryByID(m.top, ig, unsigned(ii));
        rtcReleaseGeometry(ig);
        m.inst_geom.push_back(int(in.geometry));
        m.inst_nrm.push_back(glm::transpose(glm::inverse(x.linear)));
      }
    }
    rtcCommitScene(m.top);
    m.check("building the instance scene");
  } catch (...) {
    m.release_scene();
    throw;
  }
  m.timing.build_seconds = seconds_since(t0);
  m.scene_bytes = std::size_t(std::max<long long>(0, m.live_bytes.load()));
}

namespace {

RTCRay embree_ray(const kernel::Ray& r, std::size_t i) {
  return RTCRay{r.org[0], r.org[1], r.org[2], r.tmin, r.dir[0], r.dir[1], r.dir[2], 0.0f, r.tmax, ~0u, unsigned(i), 0u};
}

void init_context(RTCIntersectContext& ctx, const EmbreeTrace& how) {
  rtcInitIntersectContext(&ctx); // Embree's default: incoherent
  if (how.api == EmbreeApi::Stream && how.coherent) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
}

// Rays per stream call: a chunk of the batch (Impl::for_chunks) at a time.
constexpr std::size_t kStreamRays = 256;

} // namespace

const char* embree_api_name(EmbreeApi api) { return api == EmbreeApi::Stream ? "rtcIntersect1M" : "rtcIntersect1"; }

void EmbreePeer::Impl::to_hit(const RTCRayHit& rh, kernel::Hit& h) const {
  h = miss_hit();
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID) return;
  int inst = int(rh.hit.instID[0]);
  int geom = inst_geom[std::size_t(inst)];
  h.t = rh.ray.tfar;
  h.prim = int(rh.hit.primID);
  bool cap = rh.hit.geomID == 1; // an end sphere: report the curve it closes
  if (cap) h.prim = caps[std::size_t(geom)][rh.hit.primID] / 2;
  h.geom = geom;
  h.inst = inst;
  glm::dvec3 n = inst_nrm[std::size_t(inst)] * glm::dvec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  double len = glm::length(n);
  if (len > 0.0) n /= len;
  for (int k = 0; k < 3; ++k) h.normal[k] = float(n[k]);
  switch (embree_prim_row(geom_type[std::size_t(geom)]).uv) {
    case HitUv::Barycentric: h.u = rh.hit.u; h.v = rh.hit.v; break;
    case HitUv::None: break;
    case HitUv::CurveParameter: h.u = cap ? float(caps[std::size_t(geom)][rh.hit.primID] % 2) : rh.hit.u; break;
  }
}

void EmbreePeer::trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits, EmbreeTrace how) {
  Impl& m = *impl_;
  if (hits.size() < rays.size())
    throw Error("embree: trace needs a hit per ray (" + std::to_string(rays.size()) + " rays, " +
                std::to_string(hits.size()) + " hits)");
  if (m.top == nullptr) throw Error("embree: trace before set_scene");
  auto t0 = std::chrono::steady_clock::now();
  m.for_chunks(rays.size(), [&](std::size_t begin, std::size_t end) {
    RTCIntersectContext ctx;
    init_context(ctx, how);
    auto fresh = [&](std::size_t i) {
      RTCRayHit rh;
      rh.ray = embree_ray(rays[i], i);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      return rh;
    };
    if (how.api == EmbreeApi::PerRay) {
      for (std::size_t i = begin; i < end; ++i) {
        hits[i] = miss_hit();
        if (!ray_valid(rays[i])) continue;
        RTCRayHit rh = fresh(i);
        rtcInitIntersectContext(&ctx);
        rtcIntersect1(m.top, &ctx, &rh);
        m.to_hit(rh, hits[i]);
      }
      return;
    }
    // The stream: the chunk's valid rays side by side (rtcIntersect1M's rays must all be
    // valid), their batch index in the ray's id.
    RTCRayHit stream[kStreamRays];
    for (std::size_t b = begin; b < end; b += kStreamRays) {
      unsigned n = 0;
      for (std::size_t i = b; i < std::min(end, b + kStreamRays); ++i) {
        hits[i] = miss_hit();
        if (ray_valid(rays[i])) stream[n++] = fresh(i);
      }
      if (n == 0) continue;
      rtcIntersect1M(m.top, &ctx, stream, n, sizeof(RTCRayHit));
      for (unsigned k = 0; k < n; ++k) m.to_hit(stream[k], hits[stream[k].ray.id]);
    }
  });
  m.timing.trace_seconds = seconds_since(t0);
  m.check("trace");
}

void EmbreePeer::occluded(std::span<const kernel::Ray> rays, std::span<std::uint8_t> occluded, EmbreeTrace how) {
  Impl& m = *impl_;
  if (occluded.size() < rays.size())
    throw Error("embree: occluded needs a flag per ray (" + std::to_string(rays.size()) + " rays, " +
                std::to_string(occluded.size()) + " flags)");
  if (m.top == nullptr) throw Error("embree: occluded before set_scene");
  auto t0 = std::chrono::steady_clock::now();
  m.for_chunks(rays.size(), [&](std::size_t begin, std::size_t end) {
    RTCIntersectContext ctx;
    init_context(ctx, how);
    if (how.api == EmbreeApi::PerRay) {
      for (std::size_t i = begin; i < end; ++i) {
        occluded[i] = 0;
        if (!ray_valid(rays[i])) continue;
        RTCRay ray = embree_ray(rays[i], i);
        rtcInitIntersectContext(&ctx);
        rtcOccluded1(m.top, &ctx, &ray);
        occluded[i] = ray.tfar < 0.0f; // Embree sets tfar to -inf when it finds any hit
      }
      return;
    }
    RTCRay stream[kStreamRays];
    for (std::size_t b = begin; b < end; b += kStreamRays) {
      unsigned n = 0;
      for (std::size_t i = b; i < std::min(end, b + kStreamRays); ++i) {
        occluded[i] = 0;
        if (ray_valid(rays[i])) stream[n++] = embree_ray(rays[i], i);
      }
      if (n == 0) continue;
      rtcOccluded1M(m.top, &ctx, stream, n, sizeof(RTCRay));
      for (unsigned k = 0; k < n; ++k) occluded[stream[k].id] = stream[k].tfar < 0.0f;
    }
  });
  m.timing.trace_seconds = seconds_since(t0);
  m.check("occluded");
}

PeerTiming EmbreePeer::timing() const { return impl_->timing; }
std::size_t EmbreePeer::bytes() const { return impl_->scene_bytes; }
std::size_t EmbreePeer::end_spheres() const { return impl_->end_spheres; }

std::string EmbreePeer::description() const {
  const Impl& m = *impl_;
  std::string d = version() + ", " + std::to_string(m.threads) + (m.threads == 1 ? " thread" : " threads") +
                  (m.robust ? ", RTC_SCENE_FLAG_ROBUST" : ", default scene flags") +
                  ", build quality medium (Embree's default)";
  bool linear = false, bezier = false, spheres = false, triangles = false;
  for (PrimType t : m.geom_type) {
    const EmbreeKind kind = embree_prim_row(t).kind;
    linear |= kind == EmbreeKind::Linear;
    bezier |= kind == EmbreeKind::Bezier;
    spheres |= kind == EmbreeKind::Spheres;
    triangles |= kind == EmbreeKind::Triangles;
  }
  std::string types;
  auto add = [&](bool on, const char* name) {
    if (!on) return;
    if (!types.empty()) types += '/';
    types += name;
  };
  add(linear, "round linear curves");
  add(bezier, m.end_spheres > 0 ? "round Bezier curves + end spheres" : "round Bezier curves");
  add(spheres, "sphere points");
  add(triangles, "triangles");
  return types.empty() ? d : d + ", " + types;
}

#else // !MASQ_HAVE_EMBREE

struct EmbreePeer::Impl {};

EmbreePeer::EmbreePeer(int /*threads*/) { throw Error(unavailable_reason()); }
EmbreePeer::~EmbreePeer() = default;
void EmbreePeer::set_scene(const Scene&, bool, CurveEnds) { throw Error(unavailable_reason()); }
const char* embree_api_name(EmbreeApi api) { return api == EmbreeApi::Stream ? "rtcIntersect1M" : "rtcIntersect1"; }
void EmbreePeer::trace(std::span<const kernel::Ray>, std::span<kernel::Hit>, EmbreeTrace) {
  throw Error(unavailable_reason());
}
void EmbreePeer::occluded(std::span<const kernel::Ray>, std::span<std::uint8_t>, EmbreeTrace) {
  throw Error(unavailable_reason());
}
PeerTiming EmbreePeer::timing() const { return {}; }
std::size_t EmbreePeer::bytes() const { return 0; }
std::size_t EmbreePeer::end_spheres() const { return 0; }
std::string EmbreePeer::description() const { return version(); }

#endif

} // namespace masq
