/// @file masq/context.h
/// Acceleration structures (Accel) and the device that traces them (Context).
#pragma once
#include "masq/scene.h"
#include "masq/types.h"
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace masq::api {

/// How an Accel is built.
struct AccelOptions {
  Method method = Method::Masq;
  Mode mode = Mode::Robust;
  /// The cubic-curve intersector (curve_isect_table).
  CurveIsect curve_isect = CurveIsect::Phantom;
  Builder builder = Builder::Sah;
  NodeFormat nodes = NodeFormat::W4;
  /// Masquerade TLAS entries as 32-byte compact records (quaternion, bfloat16 scales;
  /// default) or, when false, as the 64-byte instances RT hardware stores (same hits).
  bool compact_masquerade = true;
  /// How occlusion queries walk each BLAS (blas_occlusion_table): the same answers,
  /// found sooner or later.
  BlasOcclusion blas_occlusion = BlasOcclusion::Nearest;
  /// Threads of the host build: 0 every hardware thread, 1 serial. The structure is the
  /// same, bit for bit, with any count.
  int build_threads = 0;
};

/// Figures of a built Accel.
struct AccelStats {
  std::size_t instances = 0;   ///< TLAS entries (masq: one per thin primitive)
  std::size_t tlas_nodes = 0;  ///< wide TLAS nodes
  std::size_t blas_nodes = 0;  ///< wide BLAS nodes
  std::size_t bytes = 0;       ///< acceleration + primitive arrays as uploaded to a device
  std::size_t node_bytes = 0;  ///< TLAS and BLAS nodes alone, in the Accel's node format
  double build_seconds = 0;
  /// The method the structure was built with: the one asked for or, for Method::Auto,
  /// the candidate auto kept (Ref, Masq, Cluster; Auto itself: its per-cluster mix).
  Method method = Method::Ref;
  std::size_t primitives = 0;  ///< primitives traced (Scene::primitive_count)
};

/// A scene built for tracing with one method. Immutable once built and cheap to copy
/// (copies share the data); may be traced by several Contexts, also from several
/// threads at once. Independent of the Scene it was built from.
class Accel {
 public:
  /// Validates the scene (throws masq::Error naming the bad element) and builds the
  /// two-level BVH on the host. Each Context uploads it on first use.
  static Accel build(const Scene& scene, const AccelOptions& options = {});
  AccelStats stats() const;
  AccelOptions options() const;

  struct Impl;
  /// Internal; for the library's own use.
  const std::shared_ptr<const Impl>& impl() const { return impl_; }

 private:
  std::shared_ptr<const Impl> impl_;
};

/// Times of the last work a Context did.
struct Timing {
  double upload_seconds = 0;  ///< last Accel upload (and driver acceleration-structure build)
  double compile_seconds = 0; ///< kernel/pipeline compile of the variant used (first use only)
  double trace_seconds = 0;   ///< last trace: device time where the backend measures it, else wall time
};

/// One backend on one device. Owns its device resources; movable, not copyable (a
/// moved-from Context throws masq::Error from trace).
///
/// Thread safety: a Context must be used by one thread at a time. Distinct Contexts may
/// be used from different threads at the same time (also two on the same backend: Vulkan
/// contexts share one device and queue, and submissions to it are serialised inside the
/// library), and give the same results as when used one after the other.
class Context {
 public:
  /// Opens `backend`: "cpu", "vulkan", "opencl", "rayquery", "rtpipeline", or "best" (the first
  /// that opens of vulkan and opencl on a real GPU or accelerator, then cpu, then vulkan
  /// and opencl on a device that runs on the host's cores, such as lavapipe or PoCL,
  /// which the cpu backend outruns; `masq info` prints the order). Throws masq::BackendUnavailable naming the
  /// cause when the backend cannot run here, masq::Error for an unknown name.
  explicit Context(const std::string& backend = "best");
  /// Opens `backend` on the device `device` names: an index of `masq info`'s list for the
  /// backend's API or a case-insensitive substring of a device name ("" : the default
  /// choice, as above). Throws masq::Error for a selector that names no device (the
  /// message lists the devices there are) and for "best" or "cpu" with a device. The
  /// selector holds for this Context only; construct Contexts that name devices from one
  /// thread at a time.
  Context(const std::string& backend, const std::string& device);
  ~Context();
  Context(Context&&) noexcept;
  Context& operator=(Context&&) noexcept;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  /// Every backend compiled in, whether or not it runs here.
  static std::vector<std::string> backends();
  /// The backends that open on this machine (tries each; takes a moment).
  static std::vector<std::string> available_backends();

  std::string backend() const; ///< "cpu", "vulkan", ...
  std::string device() const;  ///< device and driver

  /// Closest hit of every ray against `accel` (uploaded on first use, kept until another
  /// Accel is traced). hits.size() must equal rays.size(). When stats is non-empty it
  /// must have rays.size() entries and receives per-ray counters.
  void trace(const Accel& accel, std::span<const Ray> rays, std::span<Hit> hits,
             std::span<RayStats> stats = {});
  std::vector<Hit> trace(const Accel& accel, std::span<const Ray> rays);

  /// Occlusion (shadow rays): occluded[i] = 1 when anything lies on ray i within
  /// [tmin, tmax]. Runs the any-hit kernel variant, which stops at the first hit found.
  void occluded(const Accel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

  Timing timing() const;
  /// Bytes this context holds on its device for the current Accel.
  std::size_t device_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace masq::api
