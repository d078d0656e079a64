// opencl bv tracer: kernels/trace_bv.cl built per (node type, counters, primitive
// types) with -D switches. All rays of a trace go up in one buffer (bounded by the
// device's largest allocation, checked below) and are dispatched in chunks of at most
// max_rays_per_dispatch (host/limit_knob.h: the watchdog bound) with ray_offset.
#include "host/trace_faults.h"
#include "host/bv_tracer.h"
#include "host/opencl/cl_runtime.h"
#include "host/opencl/cl_scene_buffers.h"
#include "host/opencl/kernel_sources.h"
#include "host/scene_variant.h"
#include "host/opencl/cl_local_size.h"
#include "masq/error.h"
#include <algorithm>
#include <chrono>
#include <map>

namespace masq {
namespace {

using opencl::check;
constexpr std::size_t kBvDummyBytes = 16; // OpenCL rejects zero-sized buffers

class OpenClBvTracer final : public BvTracer {
 public:
  OpenClBvTracer() : rt_(opencl::open_runtime()), stand_in_(opencl::stand_in_buffer(rt_)) {}
  std::string name() const override { return "opencl"; }
  TraceTiming timing() const override { return timing_; }

  void set_scene(const BvScene& scene) override {
    auto t0 = std::chrono::steady_clock::now();
    const PackedScene& p = scene.prims;
    buffers_ = opencl::upload_scene_arrays(rt_, "opencl bv", scene_array_data(scene), KernelFamily::Bv, stand_in_);
    check(rt_.queue.finish(), "clFinish (bv scene upload)");
    type_ = scene.type;
    node_count_ = int(scene.node_count());
    features_ = p.features;
    features_.mode = Mode::Robust; // the bv kernels use the robust intersectors
    have_scene_ = true;
    timing_.scene_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
             std::span<kernel::RayStats> stats) override {
    if (!have_scene_) throw Error("opencl bv: trace called before set_scene");
    const bool want_stats = !stats.empty();
    if (hits.size() != rays.size() || (want_stats && stats.size() != rays.size()))
      throw Error("opencl bv: hits/stats spans must have one entry per ray");
    if (rays.size() > std::size_t(INT32_MAX)) throw Error("opencl bv: more than 2^31-1 rays in one batch");
    cl::Kernel& k = kernel(want_stats);
    const auto start = std::chrono::steady_clock::now();
    timing_.trace_seconds = timing_.wall_seconds = timing_.upload_seconds = timing_.readback_seconds = 0;
    const std::size_t n = rays.size();
    if (n == 0) return;
    const std::size_t chunk = std::min<std::size_t>(n, max_rays_per_dispatch("opencl"));
    cl::Buffer ray_buf = scratch("rays", n * sizeof(kernel::Ray), CL_MEM_READ_ONLY);
    cl::Buffer hit_buf = scratch("hits", chunk * sizeof(kernel::Hit), CL_MEM_WRITE_ONLY);
    cl::Buffer stat_buf =
        scratch("stats", want_stats ? chunk * sizeof(kernel::RayStats) : kBvDummyBytes, CL_MEM_WRITE_ONLY);
    std::vector<cl::Event> dispatches, uploads, readbacks;
    check(rt_.queue.enqueueWriteBuffer(ray_buf, CL_FALSE, 0, n * sizeof(kernel::Ray), rays.data(), nullptr,
                                       &uploads.emplace_back()),
          "clEnqueueWriteBuffer(rays)");
    cl_uint arg = opencl::set_scene_args(k, buffers_);
    check(k.setArg(arg++, ray_buf), "clSetKernelArg(rays)");
    check(k.setArg(arg++, hit_buf), "clSetKernelArg(hits)");
    check(k.setArg(arg++, stat_buf), "clSetKernelArg(stats)");
    const cl_uint params_arg = arg;
    const opencl::WorkGroup group = opencl::kernel_work_group(rt_, k); // host/opencl/cl_local_size.h
    const cl::NDRange local = group.local > 0 ? cl::NDRange(group.local) : cl::NullRange;
    for (std::size_t c0 = 0; c0 < n; c0 += chunk) {
      const std::size_t cn = std::min(chunk, n - c0);
      // tlas_root: the node count
      const kernel::TraceParams params{int(cn), node_count_, int(c0), step_budget(std::size_t(node_count_))};
      check(k.setArg(params_arg, params), "clSetKernelArg(params)");
      const std::size_t global = opencl::padded_global(group, cn);
      check(rt_.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), local, nullptr,
                                           &dispatches.emplace_back()),
            "clEnqueueNDRangeKernel(trace_bv)");
      // In-order queue: each read completes before the next chunk overwrites the buffer.
      check(rt_.queue.enqueueReadBuffer(hit_buf, CL_FALSE, 0, cn * sizeof(kernel::Hit), hits.data() + c0, nullptr,
                                        &readbacks.emplace_back()),
            "clEnqueueReadBuffer(hits)");
      if (want_stats)
        check(rt_.queue.enqueueReadBuffer(stat_buf, CL_FALSE, 0, cn * sizeof(kernel::RayStats), stats.data() + c0,
                                          nullptr, &readbacks.emplace_back()),
              "clEnqueueReadBuffer(stats)");
    }
    check(rt_.queue.finish(), "clFinish(trace_bv)");
    timing_.trace_seconds = opencl::event_seconds(dispatches);
    timing_.upload_seconds = opencl::event_seconds(uploads);
    timing_.readback_seconds = opencl::event_seconds(readbacks);
    timing_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    check_trace_faults("opencl bv", rt_.description, hits, step_budget(std::size_t(node_count_)));
  }

 private:
  cl::Buffer scratch(const char* what, std::size_t bytes, cl_mem_flags flags) {
    if (bytes > rt_.max_alloc_bytes())
      throw Error("opencl bv: " + std::string(what) + " need " + std::to_string(bytes) +
                  " bytes, more than CL_DEVICE_MAX_MEM_ALLOC_SIZE (" + std::to_string(rt_.max_alloc_bytes()) + ")");
    cl_int err = CL_SUCCESS;
    cl::Buffer b(rt_.context, flags, std::max(bytes, kBvDummyBytes), nullptr, &err);
    check(err, "clCreateBuffer(" + std::string(what) + ")");
    return b;
  }

  cl::Kernel& kernel(bool want_stats) {
    std::string options = opencl::base_build_options(rt_) + " -D MASQ_BV_TYPE=" +
                          std::to_string(bv_type_kernel_id(type_)) +
                          opencl::variant_build_options(kernel_variant(features_, {want_stats, false}));
    auto it = kernels_.find(options);
    if (it != kernels_.end()) {
      timing_.compile_seconds = it->second.second;
      return it->second.first;
    }
    opencl::BuiltProgram built = opencl::build_program(rt_, opencl::trace_bv_source(), options, "kernels/trace_bv.cl");
    cl_int err = CL_SUCCESS;
    cl::Kernel k(built.program, "trace_bv", &err);
    check(err, "clCreateKernel(trace_bv)");
    timing_.compile_seconds = built.seconds;
    return kernels_.emplace(options, std::make_pair(k, built.seconds)).first->second.first;
  }

  opencl::Runtime rt_;
  cl::Buffer stand_in_; // the rows the bv kernel does not read (the two-level arrays)
  opencl::SceneBuffers buffers_;
  std::map<std::string, std::pair<cl::Kernel, double>> kernels_;
  BvType type_ = BvType::Scb;
  int node_count_ = 0;
  KernelFeatures features_;
  bool have_scene_ = false;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<BvTracer> make_opencl_bv_tracer() { return std::make_unique<OpenClBvTracer>(); }

} // namespace masq
