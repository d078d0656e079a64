#include "host/trace_faults.h"
#include "host/opencl/opencl_backend.h"

#include "host/opencl/cl_runtime.h"
#include "host/opencl/cl_scene_buffers.h"
#include "host/opencl/kernel_sources.h"
#include "host/device_fill.h"
#include "host/scene_variant.h"
#include "host/opencl/cl_local_size.h"
#include "masq/error.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <vector>

namespace masq {
namespace {

using opencl::check;

constexpr std::size_t kMaxWindowRays = std::size_t{1} << 30;
// OpenCL rejects zero-sized buffers; empty arrays get a dummy the kernel never reads.
constexpr std::size_t kDummyBytes = 16;

struct UploadedScene {
  opencl::SceneBuffers arrays;
  int tlas_root = -1;
  std::int32_t step_budget = 1; // kernel::TraceParams::step_budget (host/trace_faults.h)
  KernelFeatures features;
};

struct Variant {
  cl::Program program;
  cl::Kernel kernel;
  double compile_seconds = 0;
};

class OpenClBackend final : public Backend {
 public:
  explicit OpenClBackend(std::size_t chunk_rays)
      : rt_(opencl::open_runtime()), stand_in_(opencl::stand_in_buffer(rt_)),
        chunk_rays_(std::max<std::size_t>(chunk_rays, 1)) {}

  std::string name() const override { return "opencl"; }
  std::string device_name() const override { return rt_.description; }
  TraceTiming timing() const override { return timing_; }
  std::size_t fill_rays() const override { return fill_rays_for(opencl::resident_threads(rt_)); }
  std::size_t device_bytes() const override { return scene_ ? scene_->arrays.bytes : 0; }

  void set_scene(const PackedScene& scene) override {
    auto start = std::chrono::steady_clock::now();
    if (scene.tlas_root >= static_cast<std::int64_t>(scene.node_count()))
      throw Error("opencl: tlas_root " + std::to_string(scene.tlas_root) + " is outside the " +
                  std::to_string(scene.node_count()) + " nodes");
    scene_.reset(); // free the previous scene's device memory first
    UploadedScene up;
    up.arrays = opencl::upload_scene_arrays(rt_, "opencl", scene_array_data(scene), KernelFamily::TwoLevel, stand_in_);
    up.tlas_root = scene.tlas_root;
    up.step_budget = step_budget(scene.node_count());
    up.features = scene.features;
    check(rt_.queue.finish(), "clFinish (scene upload)");
    scene_ = std::move(up);
    timing_.scene_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits, std::span<kernel::RayStats> stats,
             Query query) override {
    if (!scene_) throw Error("opencl: trace called before set_scene");
    if (hits.size() != rays.size())
      throw Error("opencl: " + std::to_string(rays.size()) + " rays but " + std::to_string(hits.size()) + " hits");
    const bool want_stats = !stats.empty();
    if (want_stats && stats.size() != rays.size())
      throw Error("opencl: " + std::to_string(rays.size()) + " rays but " + std::to_string(stats.size()) + " stats");
    Variant& v = variant(want_stats, query == Query::Any);
    const auto start = std::chrono::steady_clock::now();
    timing_.compile_seconds = v.compile_seconds;
    timing_.trace_seconds = timing_.wall_seconds = timing_.upload_seconds = timing_.readback_seconds = 0;
    const std::size_t n = rays.size();
    if (n == 0) return;

    // All rays of a window live in one buffer; chunks of it are dispatched with
    // ray_offset. The window is as large as the device's largest allocation allows.
    // Both are bounded by kMaxWindowRays so ray_count and ray_offset fit the kernel's int.
    const std::size_t chunk = std::min<std::size_t>(
        {n, chunk_rays_, kMaxWindowRays, static_cast<std::size_t>(max_rays_per_dispatch("opencl"))});
    std::size_t window = std::min({n, rt_.max_alloc_bytes() / sizeof(kernel::Ray), kMaxWindowRays});
    if (window > chunk) window -= window % chunk;
    window = std::max(window, chunk);
    ensure(ray_buf_, ray_cap_, window * sizeof(kernel::Ray), CL_MEM_READ_ONLY, "rays");
    ensure(hit_buf_, hit_cap_, chunk * sizeof(kernel::Hit), CL_MEM_WRITE_ONLY, "hits");
    if (want_stats) ensure(stat_buf_, stat_cap_, chunk * sizeof(kernel::RayStats), CL_MEM_WRITE_ONLY, "stats");
    else ensure(stat_buf_, stat_cap_, kDummyBytes, CL_MEM_WRITE_ONLY, "stats");

    cl::Kernel& k = v.kernel;
    cl_uint arg = opencl::set_scene_args(k, scene_->arrays);
    check(k.setArg(arg++, ray_buf_), "clSetKernelArg(rays)");
    check(k.setArg(arg++, hit_buf_), "clSetKernelArg(hits)");
    check(k.setArg(arg++, stat_buf_), "clSetKernelArg(stats)");
    const cl_uint params_arg = arg; // kernel::TraceParams, set per chunk
    const opencl::WorkGroup group = opencl::kernel_work_group(rt_, k); // host/opencl/cl_local_size.h

    std::vector<cl::Event> events, uploads, readbacks;
    for (std::size_t w0 = 0; w0 < n; w0 += window) {
      const std::size_t wn = std::min(window, n - w0);
      check(rt_.queue.enqueueWriteBuffer(ray_buf_, CL_FALSE, 0, wn * sizeof(kernel::Ray), rays.data() + w0, nullptr,
                                         &uploads.emplace_back()),
            "clEnqueueWriteBuffer(rays)");
      for (std::size_t c0 = 0; c0 < wn; c0 += chunk) {
        const std::size_t cn = std::min(chunk, wn - c0);
        const kernel::TraceParams params{int(cn), scene_->tlas_root, int(c0), scene_->step_budget};
        check(k.setArg(params_arg, params), "clSetKernelArg(params)");
        const std::size_t global = opencl::padded_global(group, cn);
        const cl::NDRange local = group.local > 0 ? cl::NDRange(group.local) : cl::NullRange;
        cl::Event ev;
        check(rt_.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), local, nullptr, &ev),
              "clEnqueueNDRangeKernel(trace)");
        events.push_back(ev);
        // In-order queue: each read completes before the next chunk overwrites the buffer.
        check(rt_.queue.enqueueReadBuffer(hit_buf_, CL_FALSE, 0, cn * sizeof(kernel::Hit), hits.data() + w0 + c0,
                                          nullptr, &readbacks.emplace_back()),
              "clEnqueueReadBuffer(hits)");
        if (want_stats)
          check(rt_.queue.enqueueReadBuffer(stat_buf_, CL_FALSE, 0, cn * sizeof(kernel::RayStats),
                                            stats.data() + w0 + c0, nullptr, &readbacks.emplace_back()),
                "clEnqueueReadBuffer(stats)");
      }
      // The next window's upload must not overwrite rays still being traced.
      check(rt_.queue.finish(), "clFinish(trace)");
    }
    timing_.trace_seconds = opencl::event_seconds(events);
    timing_.upload_seconds = opencl::event_seconds(uploads);
    timing_.readback_seconds = opencl::event_seconds(readbacks);
    timing_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    check_trace_faults("opencl", device_name(), hits, scene_->step_budget);
  }

 private:
  void ensure(cl::Buffer& buf, std::size_t& cap, std::size_t bytes, cl_mem_flags flags, const char* what) {
    if (cap >= bytes && buf() != nullptr) return;
    if (bytes > rt_.max_alloc_bytes())
      throw Error("opencl: " + std::string(what) + " buffer needs " + std::to_string(bytes) +
                  " bytes, more than CL_DEVICE_MAX_MEM_ALLOC_SIZE (" + std::to_string(rt_.max_alloc_bytes()) + ")");
    buf = cl::Buffer();
    cl_int err = CL_SUCCESS;
    buf = cl::Buffer(rt_.context, flags, bytes, nullptr, &err);
    check(err, "clCreateBuffer(" + std::string(what) + ", " + std::to_string(bytes) + " bytes)");
    cap = bytes;
  }

  // The program variant for the current scene's features, built on first use.
  Variant& variant(bool want_stats, bool any_hit) {
    std::string options = opencl::base_build_options(rt_) +
                          opencl::variant_build_options(kernel_variant(scene_->features, {want_stats, any_hit}));
    auto it = variants_.find(options);
    if (it != variants_.end()) return it->second;
    opencl::BuiltProgram built = opencl::build_program(rt_, opencl::trace_source(), options, "kernels/trace.cl");
    Variant v;
    v.program = built.program;
    v.compile_seconds = built.seconds;
    cl_int err = CL_SUCCESS;
    v.kernel = cl::Kernel(v.program, "trace", &err);
    check(err, "clCreateKernel(trace)");
    return variants_.emplace(options, std::move(v)).first->second;
  }

  opencl::Runtime rt_;
  cl::Buffer stand_in_; // the rows the trace kernel does not read (the bv arrays)
  std::size_t chunk_rays_;
  std::optional<UploadedScene> scene_;
  std::map<std::string, Variant> variants_; // by build options
  cl::Buffer ray_buf_, hit_buf_, stat_buf_;
  std::size_t ray_cap_ = 0, hit_cap_ = 0, stat_cap_ = 0;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<Backend> make_opencl_backend(std::size_t chunk_rays) {
  return std::make_unique<OpenClBackend>(chunk_rays);
}

} // namespace masq
