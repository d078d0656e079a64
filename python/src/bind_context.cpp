// masq.Accel and masq.Context: builds and traces with the GIL released, rays in and hits
// out as numpy arrays of the library's own layouts (bindings.h), options by the names of
// the C++ option tables (masq/types.h), so a new table row is a new Python value too.
#include "arrays.h"
#include "bindings.h"
#include "rays.h"
#include "masq/context.h"
#include "masq/error.h"
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <variant>

namespace masq::py {

namespace {

// The value `name` names in `table`, or ValueError naming the argument and the choices.
template <class Table>
auto option(const Table& table, const std::string& name, ArgName arg) {
  if (const auto* row = table.find(name)) return row->value;
  throw pyb::value_error(arg.text() + ": unknown " + table.what() + " '" + name + "' (expected " + table.choices() +
                         ")");
}

api::Accel build_accel(const api::Scene& scene, const std::string& method, const std::string& mode,
                       const std::string& builder, const std::string& nodes, const std::string& curve_isect,
                       bool compact_masquerade, int build_threads, const std::string& blas_occlusion) {
  api::AccelOptions o;
  o.method = option(api::method_table, method, {"Accel.build", "method"});
  o.mode = option(api::mode_table, mode, {"Accel.build", "mode"});
  o.builder = option(api::builder_table, builder, {"Accel.build", "builder"});
  o.nodes = option(api::node_format_table, nodes, {"Accel.build", "nodes"});
  o.curve_isect = option(api::curve_isect_table, curve_isect, {"Accel.build", "curve_isect"});
  o.compact_masquerade = compact_masquerade;
  o.blas_occlusion = option(api::blas_occlusion_table, blas_occlusion, {"Accel.build", "blas_occlusion"});
  if (build_threads < 0)
    throw pyb::value_error("Accel.build: build_threads: " + std::to_string(build_threads) +
                           " (0: every hardware thread, 1: serial, n: n threads)");
  o.build_threads = build_threads;
  pyb::gil_scoped_release unlocked;
  return api::Accel::build(scene, o);
}

pyb::dict accel_options(const api::Accel& a) {
  const api::AccelOptions o = a.options();
  pyb::dict d;
  d["method"] = api::method_table.name(o.method);
  d["mode"] = api::mode_table.name(o.mode);
  d["builder"] = api::builder_table.name(o.builder);
  d["nodes"] = api::node_format_table.name(o.nodes);
  d["curve_isect"] = api::curve_isect_table.name(o.curve_isect);
  d["compact_masquerade"] = o.compact_masquerade;
  d["build_threads"] = o.build_threads;
  d["blas_occlusion"] = api::blas_occlusion_table.name(o.blas_occlusion);
  return d;
}

// The hit array to write: `out` when given (checked: hit_dtype, one record per ray in the
// rays' shape, C-contiguous, writeable), else a new one.
pyb::array hit_output(const pyb::handle& out, const std::vector<pyb::ssize_t>& shape, std::size_t rays) {
  if (out.is_none()) return pyb::array(hit_dtype(), shape);
  ArgName name{"Context.trace", "out"};
  if (!pyb::isinstance<pyb::array>(out)) throw pyb::type_error(name.text() + ": expected a masq.hit_dtype array");
  auto a = pyb::reinterpret_borrow<pyb::array>(out);
  if (!a.dtype().equal(hit_dtype()))
    throw pyb::type_error(name.text() + ": expected dtype masq.hit_dtype, got " + pyb::str(a.dtype()).cast<std::string>());
  if (std::vector<pyb::ssize_t>(a.shape(), a.shape() + a.ndim()) != shape)
    throw pyb::value_error(name.text() + ": expected " + std::to_string(rays) + " records of shape " +
                           shape_text(shape) + " (one per ray), got shape " + shape_text(a));
  // Written in place by the library, so it cannot be a copy: strided arrays are refused.
  if (!(a.flags() & pyb::array::c_style)) throw pyb::value_error(name.text() + ": the array is not C-contiguous");
  if (!a.writeable()) throw pyb::value_error(name.text() + ": the array is read-only");
  return a;
}

// The hits, and with `stats` the per-ray counters, of the rays in the rays' shape.
std::pair<pyb::array, pyb::array> trace_rays(api::Context& ctx, const api::Accel& accel, const pyb::handle& origins,
                                             const pyb::handle& directions, const pyb::handle& tmin,
                                             const pyb::handle& tmax, bool stats, const pyb::handle& out) {
  RayInput in = ray_input(origins, directions, tmin, tmax, "Context.trace");
  const std::size_t n = in.rays.size();
  pyb::array hits = hit_output(out, in.shape, n);
  pyb::array counters = pyb::array(stats_dtype(), stats ? in.shape : std::vector<pyb::ssize_t>{0});
  std::span<api::Hit> hit_span{static_cast<api::Hit*>(hits.mutable_data()), n};
  std::span<api::RayStats> stat_span;
  if (stats) stat_span = {static_cast<api::RayStats*>(counters.mutable_data()), n};
  {
    pyb::gil_scoped_release unlocked;
    ctx.trace(accel, in.rays, hit_span, stat_span);
  }
  return {hits, counters};
}

pyb::array trace(api::Context& ctx, const api::Accel& accel, const ArrayLike& origins,
                 const OptionalArrayLike& directions, const OptionalArrayLike& tmin, const OptionalArrayLike& tmax,
                 StatsOff, const OptionalArray& out) {
  return trace_rays(ctx, accel, origins, directions, tmin, tmax, false, out).first;
}

HitsAndStats trace_with_stats(api::Context& ctx, const api::Accel& accel, const ArrayLike& origins,
                            const OptionalArrayLike& directions, const OptionalArrayLike& tmin,
                            const OptionalArrayLike& tmax, StatsOn, const OptionalArray& out) {
  auto [hits, counters] = trace_rays(ctx, accel, origins, directions, tmin, tmax, true, out);
  return HitsAndStats(pyb::make_tuple(hits, counters));
}

pyb::array occluded(api::Context& ctx, const api::Accel& accel, const ArrayLike& origins,
                    const OptionalArrayLike& directions, const OptionalArrayLike& tmin, const OptionalArrayLike& tmax) {
  RayInput in = ray_input(origins, directions, tmin, tmax, "Context.occluded");
  pyb::array_t<bool> out(in.shape);
  // numpy's bool is one byte holding 0 or 1: what Context::occluded writes.
  static_assert(sizeof(bool) == sizeof(std::uint8_t));
  std::span<std::uint8_t> flags{reinterpret_cast<std::uint8_t*>(out.mutable_data()), in.rays.size()};
  pyb::gil_scoped_release unlocked;
  ctx.occluded(accel, in.rays, flags);
  return out;
}

// The method an Accel was built with: the one asked for, or what auto kept ("mix": its
// per-cluster mix, which has no name of its own in the method table).
std::string kept_method(const api::AccelStats& s) {
  return s.method == api::Method::Auto ? "mix" : api::method_table.name(s.method);
}

std::string accel_repr(const api::Accel& a) {
  const api::AccelStats s = a.stats();
  const api::AccelOptions o = a.options();
  std::string method = kept_method(s);
  if (o.method != s.method || s.method == api::Method::Auto)
    method += " (chosen by " + std::string(api::method_table.name(o.method)) + ")";
  return "<masq.Accel method=" + method + " mode=" + api::mode_table.name(o.mode) +
         " nodes=" + api::node_format_table.name(o.nodes) + " primitives=" + std::to_string(s.primitives) +
         " instances=" + std::to_string(s.instances) + " bytes=" + std::to_string(s.bytes) + ">";
}

pyb::dict timing(const api::Context& ctx) {
  const api::Timing t = ctx.timing();
  pyb::dict d;
  d["upload_seconds"] = t.upload_seconds;
  d["compile_seconds"] = t.compile_seconds;
  d["trace_seconds"] = t.trace_seconds;
  return d;
}

} // namespace

void bind_context(pyb::module_& m) {
  pyb::class_<api::AccelStats>(m, "AccelStats", "Figures of a built Accel.")
      .def_readonly("instances", &api::AccelStats::instances, "TLAS entries (masq: one per thin primitive)")
      .def_readonly("tlas_nodes", &api::AccelStats::tlas_nodes)
      .def_readonly("blas_nodes", &api::AccelStats::blas_nodes)
      .def_readonly("bytes", &api::AccelStats::bytes, "acceleration + primitive arrays as uploaded to a device")
      .def_readonly("node_bytes", &api::AccelStats::node_bytes)
      .def_readonly("build_seconds", &api::AccelStats::build_seconds)
      .def_readonly("primitives", &api::AccelStats::primitives, "int: primitives traced (Scene.primitive_count)")
      .def_property_readonly("method", &kept_method,
                             "str: the method built, the one asked for or what method='auto' kept (ref, masq, "
                             "cluster, or mix for its per-cluster mix)")
      .def("__repr__", [](const api::AccelStats& s) {
        return "<masq.AccelStats method=" + kept_method(s) + " primitives=" + std::to_string(s.primitives) +
               " instances=" + std::to_string(s.instances) + " tlas_nodes=" +
               std::to_string(s.tlas_nodes) + " blas_nodes=" + std::to_string(s.blas_nodes) +
               " bytes=" + std::to_string(s.bytes) + " build_seconds=" + std::to_string(s.build_seconds) + ">";
      });

  pyb::class_<api::Accel>(m, "Accel", "A scene built for tracing with one method; immutable, shareable.")
      .def_static("build", &build_accel, pyb::arg("scene"), pyb::arg("method") = "masq", pyb::arg("mode") = "robust",
                  pyb::arg("builder") = "sah", pyb::arg("nodes") = "w4", pyb::arg("curve_isect") = "phantom",
                  pyb::arg("compact_masquerade") = true, pyb::arg("build_threads") = 0,
                  pyb::arg("blas_occlusion") = "nearest",
                  ("Builds the two-level BVH on the host (the GIL is released). method: " + api::method_table.choices() +
                   "; mode: " + api::mode_table.choices() + "; builder: " + api::builder_table.choices() +
                   "; nodes: " + api::node_format_table.choices() + "; curve_isect: " + api::curve_isect_table.choices() +
                   "; blas_occlusion: " + api::blas_occlusion_table.choices() +
                   " (masq.options lists each with its meaning).")
                      .c_str())
      .def_property_readonly("stats", &api::Accel::stats)
      .def_property_readonly("options", &accel_options, "dict: the options as given (method may be 'auto')")
      .def_property_readonly(
          "method", [](const api::Accel& a) { return kept_method(a.stats()); },
          "str: the method built, options['method'] or for 'auto' the one it kept (ref, masq, cluster, or mix for "
          "its per-cluster mix)")
      .def("__repr__", &accel_repr);

  pyb::class_<api::Context>(m, "Context", R"(One backend on one device. Use it from one thread at a time.)")
      .def(pyb::init([](const std::string& backend, std::optional<std::variant<long, std::string>> device) {
             // An integer device is an index of `masq info`'s list, as the string "0" is.
             std::optional<std::string> selector;
             if (device) selector = std::holds_alternative<long>(*device) ? std::to_string(std::get<long>(*device))
                                                                          : std::get<std::string>(*device);
             pyb::gil_scoped_release unlocked;
             return selector ? api::Context(backend, *selector) : api::Context(backend);
           }),
           pyb::arg("backend") = "best", pyb::arg("device") = pyb::none(),
           "backend: a name of masq.backends() or 'best'; device: an index (int or str) of `masq info`'s list or a device "
           "name substring (GPU backends). Raises masq.BackendUnavailable when it cannot run here.")
      .def_static("backends", &api::Context::backends, "Every backend compiled in.")
      .def_static("available_backends", &api::Context::available_backends, "The backends that open here.")
      .def_property_readonly("backend", &api::Context::backend)
      .def_property_readonly("device", &api::Context::device)
      // Two overloads, told apart by stats, so that the signatures say what each returns.
      .def("trace", &trace, pyb::arg("accel"), pyb::arg("origins"), pyb::arg("directions") = pyb::none(),
           pyb::arg("tmin") = pyb::none(), pyb::arg("tmax") = pyb::none(), pyb::kw_only(), pyb::arg("stats") = false,
           pyb::arg("out") = pyb::none(),
           "Closest hits. Rays: origins and directions of shape (..., 3), broadcast against each other; or (..., 6) "
           "rays (origin, direction) with directions left out; or one masq.ray_dtype array of any shape (read in "
           "place when C-contiguous). tmin, tmax: numbers or arrays broadcast against the rays (None: 0 and +inf; "
           "a ray_dtype array holds its own). Returns a masq.hit_dtype array of the rays' shape (prim < 0: no hit; "
           "`out`, when given, is written and returned).")
      .def("trace", &trace_with_stats, pyb::arg("accel"), pyb::arg("origins"), pyb::arg("directions") = pyb::none(),
           pyb::arg("tmin") = pyb::none(), pyb::arg("tmax") = pyb::none(), pyb::kw_only(), pyb::arg("stats"),
           pyb::arg("out") = pyb::none(),
           "With stats=True: (hits, per-ray counters), the counters a masq.stats_dtype array of the rays' shape.")
      .def("occluded", &occluded, pyb::arg("accel"), pyb::arg("origins"), pyb::arg("directions") = pyb::none(),
           pyb::arg("tmin") = pyb::none(), pyb::arg("tmax") = pyb::none(),
           "Shadow rays, given as to trace: a bool array of the rays' shape, True where anything lies on the ray "
           "within [tmin, tmax].")
      .def_property_readonly("timing", &timing,
                             "Seconds of the last upload, the variant's compile (first use) and the last trace.")
      .def_property_readonly("device_bytes", &api::Context::device_bytes)
      .def("__repr__", [](const api::Context& c) { return "<masq.Context " + c.backend() + " on " + c.device() + ">"; });
}

} // namespace masq::py
