// One interface for every way masq traces rays: cpu (kernel source compiled as C++),
// vulkan (compute shaders), opencl, rayquery (Vulkan ray query on the driver's own
// acceleration structures), rtpipeline (the Vulkan ray-tracing pipeline on the same
// structures). The drivers' front door to host/ (with host/bv_tracer.h; the CLI, bench
// and stress include no other host/ header: scripts/check_layers.py), so it also brings
// what they ask about the backends: the devices each API has and the selectors that pick
// one (host/device_list.h), the stack sizes the kernels compile for a scene
// (host/stack_size.h).
#pragma once
#include "bvh/packed_scene.h"
#include "host/device_list.h"
#include "host/stack_size.h"
#include "masq/error.h"
#include "masq/names.h"
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace masq {

// BackendUnavailable (one line: "<backend>: <why>") is defined in the public
// include/masq/error.h.

enum class Query { Closest, Any };
inline constexpr NameRow<Query> query_rows[] = {
    {Query::Closest, "closest", "the closest hit"},
    {Query::Any, "any", "the first hit found, which ends the ray: occlusion"},
};
inline constexpr NameTable query_table{"query", query_rows};
inline const char* query_name(Query q) { return query_table.name(q); }

struct TraceTiming {
  double scene_seconds = 0;   // upload + driver acceleration-structure build
  double compile_seconds = 0; // kernel/pipeline compile of the variant used (first use)
  double trace_seconds = 0;   // last trace: device time (Vulkan timestamps, OpenCL events) or wall (cpu)
  // The last trace on the host clock, the kernel variant ready: from the call to its hits
  // and counters in host memory (every chunk's upload, dispatch, wait and readback), and
  // the parts of it spent writing rays to the device and reading results back (Vulkan:
  // host time of the copies; OpenCL: the transfer commands' device time; cpu: 0, it
  // traces in place). wall - trace - upload - readback is submission and waiting.
  double wall_seconds = 0;
  double upload_seconds = 0;
  double readback_seconds = 0;
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string name() const = 0;
  virtual std::string device_name() const = 0;   // device and driver version
  // Uploads (and for rayquery and rtpipeline builds) the scene; replaces any previous one.
  virtual void set_scene(const PackedScene& scene) = 0;
  // For every ray, the closest hit (Query::Closest) or, for occlusion/shadow rays, the
  // first hit found (Query::Any: a kernel variant that stops there; its hit is some hit
  // in [tmin, tmax], not necessarily the closest; a miss means unoccluded). stats empty:
  // the counter-free variant runs; else it must have rays.size() entries and the stats
  // variant runs.
  virtual void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
                     std::span<kernel::RayStats> stats, Query query = Query::Closest) = 0;
  virtual TraceTiming timing() const = 0;
  // Bytes the backend holds on the device for the current scene (acceleration + primitives).
  virtual std::size_t device_bytes() const = 0;
  // Rays one trace needs to keep every lane of the device busy (host/device_fill.h: a
  // few waves of the threads it runs at once); 0 when the device does not say.
  virtual std::size_t fill_rays() const { return 0; }
};

class BvTracer; // host/bv_tracer.h

// A row of the backend registry (host/registry/backend_registry.cpp): how to open the backend,
// whether it also traces binary bounding-volume hierarchies, and its place in "best".
struct BackendRow {
  const char* name;
  const char* help;
  std::unique_ptr<Backend> (*make)();     // throws BackendUnavailable (one line naming the cause)
  std::unique_ptr<BvTracer> (*make_bv)(); // nullptr: no bv kernels for this backend
  int best_rank;                          // "best" tries rank 1 first, then 2...; 0: never
  const char* device_api;                 // the device_api_table row whose selector picks its device
                                          // (host/device_choice.h); nullptr: runs on the host
  bool driver_traversal;                  // the driver's own acceleration structures and traversal: node
                                          // visits and transforms are not observable (counters -1), no
                                          // kernel stacks; isect_calls counts the driver's candidates
};
// Every backend compiled in, in the order lists, defaults and reports use.
extern const NameTable<BackendRow> backend_table;

const std::vector<std::string>& backend_names(); // backend_table's names
// Whether `backend` names a row with driver_traversal (false for a name of no row).
bool driver_traversal(std::string_view backend);
// Throws BackendUnavailable (one line naming the cause) when it cannot run here,
// masq::Error for a name the registry does not hold.
std::unique_ptr<Backend> make_backend(std::string_view name);
// "best": the backends in the order it tries them: those whose device is a real GPU or
// accelerator (by best_rank), then cpu, then those whose device runs on the host's cores
// (lavapipe, PoCL), which the cpu backend outruns.
std::vector<std::string> best_backend_order();
// The first backend of best_backend_order that opens here; throws BackendUnavailable with
// every one's cause when none does.
std::unique_ptr<Backend> make_best_backend();

} // namespace masq
