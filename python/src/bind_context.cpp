// masq.Accel and masq.Context: builds and traces with the GIL released, rays in and hits
// out as numpy arrays of the library's own layouts (bindings.h), options by the names of
// the C++ option tables (masq/types.h), so a new table row is a new Python value too.
#include <variant>
#include "arrays.h"
#include "bindings.h"
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

// The rays of a trace: a ray_dtype array as it lies, or origins and directions (and
// tmin, tmax) packed into the library's Ray structs. An infinite tmax (Python's default
// bound) becomes the largest float, which every backend's arithmetic handles.
struct RayInput {
  pyb::array given;                       // a ray_dtype array used in place, or empty
  std::vector<api::Ray>& packed = buffer(); // else the rays packed here
  std::span<const api::Ray> rays;

  // Packed rays reuse one buffer per thread: a fresh one would cost its page faults on
  // every trace (a million rays: 32 MB).
  static std::vector<api::Ray>& buffer() {
    thread_local std::vector<api::Ray> rays;
    return rays;
  }
};

// Checks a ray_dtype array; returns whether any tmax is +inf (allowed, but replaced).
bool check_ray_array(const pyb::array& a, const char* function) {
  ArgName name{function, "rays"};
  if (a.ndim() != 1) throw pyb::value_error(name.text() + ": a ray_dtype array must be 1-D");
  if (!(a.flags() & pyb::array::c_style))
    throw pyb::value_error(name.text() + ": the array is not C-contiguous; pass numpy.ascontiguousarray(rays)");
  const auto* r = static_cast<const api::Ray*>(a.data());
  static_assert(sizeof(api::Ray) == 8 * sizeof(float));
  // One pass over the rays in the common case; the slow scan only when something is not
  // finite, to name it or to find an infinite tmax.
  if (!any_nonfinite(reinterpret_cast<const float*>(r), 8 * static_cast<std::size_t>(a.shape(0)))) return false;
  bool infinite_tmax = false;
  for (pyb::ssize_t i = 0; i < a.shape(0); ++i) {
    infinite_tmax |= std::isinf(r[i].tmax);
    const float v[8] = {r[i].org.x, r[i].org.y, r[i].org.z, r[i].tmin, r[i].dir.x, r[i].dir.y, r[i].dir.z, r[i].tmax};
    for (int k = 0; k < 8; ++k)
      if (std::isnan(v[k]) || (k != 7 && std::isinf(v[k])))
        throw pyb::value_error(name.text() + ": ray " + std::to_string(i) + " has a " +
                               (std::isnan(v[k]) ? "NaN" : "infinite") + " " +
                               (k < 3 ? "origin" : k == 3 ? "tmin" : k < 7 ? "direction" : "tmax") +
                               " (coordinates and ray bounds must be finite; tmax may be +inf)");
  }
  return infinite_tmax;
}

// tmax as the kernels take it: +inf (Python's "no bound") as the largest float.
float largest_bound(float tmax) {
  return tmax == std::numeric_limits<float>::infinity() ? std::numeric_limits<float>::max() : tmax;
}

RayInput ray_input(const pyb::handle& origins, const pyb::handle& directions, const pyb::handle& tmin,
                   const pyb::handle& tmax, const char* function) {
  RayInput in;
  if (pyb::isinstance<pyb::array>(origins) &&
      pyb::reinterpret_borrow<pyb::array>(origins).dtype().equal(ray_dtype())) {
    if (!directions.is_none())
      throw pyb::value_error(std::string(function) + ": directions: not used with a ray_dtype array (it holds them)");
    in.given = pyb::reinterpret_borrow<pyb::array>(origins);
    const bool infinite_tmax = check_ray_array(in.given, function);
    in.rays = {static_cast<const api::Ray*>(in.given.data()), static_cast<std::size_t>(in.given.shape(0))};
    if (!infinite_tmax) return in;
    in.packed.assign(in.rays.begin(), in.rays.end());
    in.given = pyb::array();
    for (api::Ray& r : in.packed) r.tmax = largest_bound(r.tmax);
  } else {
    if (directions.is_none())
      throw pyb::type_error(std::string(function) +
                            ": directions: missing (pass origins and directions as (n, 3) arrays, or one "
                            "masq.ray_dtype array)");
    auto o = float_rows(origins, {function, "origins"}, 3);
    const std::size_t n = row_count(o);
    auto d = float_rows(directions, {function, "directions"}, 3, static_cast<long>(n));
    PerRowFloat t0 = per_row_float(tmin, {function, "tmin"}, n);
    PerRowFloat t1 = per_row_float(tmax, {function, "tmax"}, n, true);
    in.packed.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const float* po = o.data() + 3 * i;
      const float* pd = d.data() + 3 * i;
      in.packed[i] = {{po[0], po[1], po[2]}, t0[i], {pd[0], pd[1], pd[2]}, largest_bound(t1[i])};
    }
  }
  in.rays = in.packed;
  return in;
}

api::Accel build_accel(const api::Scene& scene, const std::string& method, const std::string& mode,
                       const std::string& builder, const std::string& nodes, const std::string& curve_isect,
                       bool compact_masquerade, int build_threads) {
  api::AccelOptions o;
  o.method = option(api::method_table, method, {"Accel.build", "method"});
  o.mode = option(api::mode_table, mode, {"Accel.build", "mode"});
  o.builder = option(api::builder_table, builder, {"Accel.build", "builder"});
  o.nodes = option(api::node_format_table, nodes, {"Accel.build", "nodes"});
  o.curve_isect = option(api::curve_isect_table, curve_isect, {"Accel.build", "curve_isect"});
  o.compact_masquerade = compact_masquerade;
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
  return d;
}

// The hit array to write: `out` when given (checked: hit_dtype, one record per ray,
// C-contiguous, writeable), else a new one.
pyb::array hit_output(const pyb::handle& out, std::size_t rays) {
  if (out.is_none()) return record_array(hit_dtype(), rays);
  ArgName name{"Context.trace", "out"};
  if (!pyb::isinstance<pyb::array>(out)) throw pyb::type_error(name.text() + ": expected a masq.hit_dtype array");
  auto a = pyb::reinterpret_borrow<pyb::array>(out);
  if (!a.dtype().equal(hit_dtype()))
    throw pyb::type_error(name.text() + ": expected dtype masq.hit_dtype, got " + pyb::str(a.dtype()).cast<std::string>());
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != rays)
    throw pyb::value_error(name.text() + ": expected " + std::to_string(rays) + " records (one per ray)");
  if (!(a.flags() & pyb::array::c_style)) throw pyb::value_error(name.text() + ": the array is not C-contiguous");
  if (!a.writeable()) throw pyb::value_error(name.text() + ": the array is read-only");
  return a;
}

pyb::object trace(api::Context& ctx, const api::Accel& accel, const pyb::handle& origins, const pyb::handle& directions,
                  const pyb::handle& tmin, const pyb::handle& tmax, bool stats, const pyb::handle& out) {
  RayInput in = ray_input(origins, directions, tmin, tmax, "Context.trace");
  pyb::array hits = hit_output(out, in.rays.size());
  pyb::array counters = record_array(stats_dtype(), stats ? in.rays.size() : 0);
  std::span<api::Hit> hit_span{static_cast<api::Hit*>(hits.mutable_data()), in.rays.size()};
  std::span<api::RayStats> stat_span;
  if (stats) stat_span = {static_cast<api::RayStats*>(counters.mutable_data()), in.rays.size()};
  {
    pyb::gil_scoped_release unlocked;
    ctx.trace(accel, in.rays, hit_span, stat_span);
  }
  if (stats) return pyb::make_tuple(hits, counters);
  return std::move(hits);
}

pyb::array occluded(api::Context& ctx, const api::Accel& accel, const pyb::handle& origins,
                    const pyb::handle& directions, const pyb::handle& tmin, const pyb::handle& tmax) {
  RayInput in = ray_input(origins, directions, tmin, tmax, "Context.occluded");
  pyb::array_t<bool> out(static_cast<pyb::ssize_t>(in.rays.size()));
  // numpy's bool is one byte holding 0 or 1: what Context::occluded writes.
  static_assert(sizeof(bool) == sizeof(std::uint8_t));
  std::span<std::uint8_t> flags{reinterpret_cast<std::uint8_t*>(out.mutable_data()), in.rays.size()};
  pyb::gil_scoped_release unlocked;
  ctx.occluded(accel, in.rays, flags);
  return out;
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
      .def("__repr__", [](const api::AccelStats& s) {
        return "<masq.AccelStats instances=" + std::to_string(s.instances) + " tlas_nodes=" +
               std::to_string(s.tlas_nodes) + " blas_nodes=" + std::to_string(s.blas_nodes) +
               " bytes=" + std::to_string(s.bytes) + " build_seconds=" + std::to_string(s.build_seconds) + ">";
      });

  pyb::class_<api::Accel>(m, "Accel", "A scene built for tracing with one method; immutable, shareable.")
      .def_static("build", &build_accel, pyb::arg("scene"), pyb::arg("method") = "masq", pyb::arg("mode") = "robust",
                  pyb::arg("builder") = "sah", pyb::arg("nodes") = "w4", pyb::arg("curve_isect") = "phantom",
                  pyb::arg("compact_masquerade") = true, pyb::arg("build_threads") = 0,
                  ("Builds the two-level BVH on the host (the GIL is released). method: " + api::method_table.choices() +
                   "; mode: " + api::mode_table.choices() + "; builder: " + api::builder_table.choices() +
                   "; nodes: " + api::node_format_table.choices() + "; curve_isect: " + api::curve_isect_table.choices() +
                   " (masq.options lists each with its meaning).")
                      .c_str())
      .def_property_readonly("stats", &api::Accel::stats)
      .def_property_readonly("options", &accel_options);

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
      .def("trace", &trace, pyb::arg("accel"), pyb::arg("origins"), pyb::arg("directions") = pyb::none(),
           pyb::arg("tmin") = 0.0, pyb::arg("tmax") = std::numeric_limits<double>::infinity(),
           pyb::arg("stats") = false, pyb::arg("out") = pyb::none(),
           "Closest hits: origins and directions (n, 3) with tmin, tmax numbers or (n,) arrays, or one "
           "masq.ray_dtype array (used in place). Returns a masq.hit_dtype array (prim < 0: no hit; `out`, "
           "when given, is written and returned), and with stats=True also per-ray counters (masq.stats_dtype).")
      .def("occluded", &occluded, pyb::arg("accel"), pyb::arg("origins"), pyb::arg("directions") = pyb::none(),
           pyb::arg("tmin") = 0.0, pyb::arg("tmax") = std::numeric_limits<double>::infinity(),
           "Shadow rays: a bool array, True where anything lies on the ray within [tmin, tmax].")
      .def_property_readonly("timing", &timing,
                             "Seconds of the last upload, the variant's compile (first use) and the last trace.")
      .def_property_readonly("device_bytes", &api::Context::device_bytes)
      .def("__repr__", [](const api::Context& c) { return "<masq.Context " + c.backend() + " on " + c.device() + ">"; });
}

} // namespace masq::py
