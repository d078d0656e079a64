// masq.Scene: scenes from files and from numpy arrays. Each add_* checks its arrays
// (arrays.h) and packs them into the public API's primitive structs; the Scene copies
// them in, so the caller's arrays may change afterwards. Read back: geometry(i) (one
// row per primitive type), bounds, camera; and the rays of cameras (pinhole_rays).
#include "arrays.h"
#include "bindings.h"
#include "masq/scene.h"
#include <cmath>
#include <filesystem>
#include <optional>
#include <pybind11/stl/filesystem.h>
#include <cstring>
#include "masq/error.h"

namespace masq::py {

namespace {

using api::Vec3;

Vec3 vec3_at(const float* p) { return {p[0], p[1], p[2]}; }

std::uint32_t add_triangles(api::Scene& scene, const ArrayLike& vertices, const ArrayLike& indices) {
  auto v = float_rows(vertices, {"Scene.add_triangles", "vertices"}, 3);
  std::vector<std::uint32_t> idx = index_rows(indices, {"Scene.add_triangles", "indices"}, 3);
  std::vector<Vec3> verts(row_count(v));
  // Vec3 is three packed floats: the float32 rows are its layout.
  static_assert(sizeof(Vec3) == 3 * sizeof(float));
  if (!verts.empty()) std::memcpy(static_cast<void*>(verts.data()), v.data(), verts.size() * sizeof(Vec3));
  for (std::size_t i = 0; i < idx.size(); ++i)
    if (idx[i] >= verts.size())
      throw pyb::value_error("Scene.add_triangles: indices: row " + std::to_string(i / 3) + " names vertex " +
                             std::to_string(idx[i]) + " of " + std::to_string(verts.size()));
  pyb::gil_scoped_release unlocked;
  return scene.add_triangles(verts, idx);
}

std::uint32_t add_capsules(api::Scene& scene, const ArrayLike& a, const ArrayLike& b, const ArrayLike& radius) {
  auto pa = float_rows(a, {"Scene.add_capsules", "a"}, 3);
  auto pb = float_rows(b, {"Scene.add_capsules", "b"}, 3, static_cast<long>(row_count(pa)));
  PerRowFloat r = per_row_float(radius, {"Scene.add_capsules", "radius"}, row_count(pa));
  std::vector<api::Capsule> caps(row_count(pa));
  for (std::size_t i = 0; i < caps.size(); ++i) caps[i] = {vec3_at(pa.data() + 3 * i), vec3_at(pb.data() + 3 * i), r[i]};
  return scene.add_capsules(caps);
}

std::uint32_t add_round_cones(api::Scene& scene, const ArrayLike& a, const ArrayLike& ra, const ArrayLike& b,
                              const ArrayLike& rb) {
  auto pa = float_rows(a, {"Scene.add_round_cones", "a"}, 3);
  const std::size_t n = row_count(pa);
  auto pb = float_rows(b, {"Scene.add_round_cones", "b"}, 3, static_cast<long>(n));
  PerRowFloat r0 = per_row_float(ra, {"Scene.add_round_cones", "ra"}, n);
  PerRowFloat r1 = per_row_float(rb, {"Scene.add_round_cones", "rb"}, n);
  std::vector<api::RoundCone> round_cones(n);
  for (std::size_t i = 0; i < n; ++i) round_cones[i] = {vec3_at(pa.data() + 3 * i), r0[i], vec3_at(pb.data() + 3 * i), r1[i]};
  return scene.add_round_cones(round_cones);
}

std::uint32_t add_spheres(api::Scene& scene, const ArrayLike& centers, const ArrayLike& radius) {
  auto c = float_rows(centers, {"Scene.add_spheres", "centers"}, 3);
  PerRowFloat r = per_row_float(radius, {"Scene.add_spheres", "radius"}, row_count(c));
  std::vector<api::Sphere> spheres(row_count(c));
  for (std::size_t i = 0; i < spheres.size(); ++i) spheres[i] = {vec3_at(c.data() + 3 * i), r[i]};
  return scene.add_spheres(spheres);
}

std::uint32_t add_curves(api::Scene& scene, const ArrayLike& points, const ArrayLike& radius) {
  auto p = float_blocks(points, {"Scene.add_curves", "points"}, 4, 3);
  PerRowFloat r = per_row_float(radius, {"Scene.add_curves", "radius"}, row_count(p));
  std::vector<api::Curve> curves(row_count(p));
  for (std::size_t i = 0; i < curves.size(); ++i) {
    for (int k = 0; k < 4; ++k) curves[i].p[k] = vec3_at(p.data() + 12 * i + 3 * k);
    curves[i].radius = r[i];
  }
  return scene.add_curves(curves);
}

std::uint32_t add_ribbons(api::Scene& scene, const ArrayLike& p0, const ArrayLike& r0, const ArrayLike& p1,
                          const ArrayLike& r1, const ArrayLike& normal) {
  auto a = float_rows(p0, {"Scene.add_ribbons", "p0"}, 3);
  const std::size_t n = row_count(a);
  auto b = float_rows(p1, {"Scene.add_ribbons", "p1"}, 3, static_cast<long>(n));
  auto nr = float_rows(normal, {"Scene.add_ribbons", "normal"}, 3, static_cast<long>(n));
  PerRowFloat w0 = per_row_float(r0, {"Scene.add_ribbons", "r0"}, n);
  PerRowFloat w1 = per_row_float(r1, {"Scene.add_ribbons", "r1"}, n);
  std::vector<api::Ribbon> ribbons(n);
  for (std::size_t i = 0; i < n; ++i)
    ribbons[i] = {vec3_at(a.data() + 3 * i), w0[i], vec3_at(b.data() + 3 * i), w1[i], vec3_at(nr.data() + 3 * i)};
  return scene.add_ribbons(ribbons);
}

// ---- read back: a geometry as a dict of numpy arrays, by one row per primitive type

// An (n, 3) float32 array of get(item) for each item.
template <class T, class Get>
pyb::array_t<float> points(const std::vector<T>& items, Get get) {
  pyb::array_t<float> out(std::vector<pyb::ssize_t>{static_cast<pyb::ssize_t>(items.size()), 3});
  float* p = out.mutable_data();
  for (const T& item : items) {
    const Vec3 v = get(item);
    *p++ = v.x, *p++ = v.y, *p++ = v.z;
  }
  return out;
}

// An (n,) float32 array of get(item) for each item.
template <class T, class Get>
pyb::array_t<float> values(const std::vector<T>& items, Get get) {
  pyb::array_t<float> out(static_cast<pyb::ssize_t>(items.size()));
  float* p = out.mutable_data();
  for (const T& item : items) *p++ = get(item);
  return out;
}

// b - a scaled to unit length (zero for a point).
Vec3 unit_from(const Vec3& a, const Vec3& b) {
  const float x = b.x - a.x, y = b.y - a.y, z = b.z - a.z;
  const float l = std::sqrt(x * x + y * y + z * z);
  return l > 0 ? Vec3{x / l, y / l, z / l} : Vec3{};
}

// A cubic's direction at its middle, B'(1/2) = 3/4 (p3 + p2 - p1 - p0), as a unit vector.
Vec3 curve_tangent(const api::Curve& c) {
  const auto& p = c.p;
  return unit_from({p[0].x + p[1].x, p[0].y + p[1].y, p[0].z + p[1].z},
                   {p[2].x + p[3].x, p[2].y + p[3].y, p[2].z + p[3].z});
}

void add_strands(pyb::dict& d, const api::GeometryData& g) {
  pyb::array_t<std::int32_t> ids(static_cast<pyb::ssize_t>(g.strands.size()));
  for (std::size_t i = 0; i < g.strands.size(); ++i) ids.mutable_data()[i] = static_cast<std::int32_t>(g.strands[i]);
  d["strands"] = ids;
}

void triangle_arrays(pyb::dict& d, const api::GeometryData& g) {
  d["vertices"] = points(g.vertices, [](const Vec3& v) { return v; });
  pyb::array_t<std::uint32_t> idx(std::vector<pyb::ssize_t>{static_cast<pyb::ssize_t>(g.indices.size() / 3), 3});
  if (!g.indices.empty()) std::memcpy(idx.mutable_data(), g.indices.data(), g.indices.size() * sizeof(std::uint32_t));
  d["indices"] = idx;
}
void capsule_arrays(pyb::dict& d, const api::GeometryData& g) {
  d["a"] = points(g.capsules, [](const api::Capsule& c) { return c.a; });
  d["b"] = points(g.capsules, [](const api::Capsule& c) { return c.b; });
  d["radius"] = values(g.capsules, [](const api::Capsule& c) { return c.radius; });
  d["tangents"] = points(g.capsules, [](const api::Capsule& c) { return unit_from(c.a, c.b); });
  add_strands(d, g);
}
void round_cone_arrays(pyb::dict& d, const api::GeometryData& g) {
  d["a"] = points(g.round_cones, [](const api::RoundCone& c) { return c.a; });
  d["ra"] = values(g.round_cones, [](const api::RoundCone& c) { return c.ra; });
  d["b"] = points(g.round_cones, [](const api::RoundCone& c) { return c.b; });
  d["rb"] = values(g.round_cones, [](const api::RoundCone& c) { return c.rb; });
  d["tangents"] = points(g.round_cones, [](const api::RoundCone& c) { return unit_from(c.a, c.b); });
  add_strands(d, g);
}
void sphere_arrays(pyb::dict& d, const api::GeometryData& g) {
  d["centers"] = points(g.spheres, [](const api::Sphere& s) { return s.center; });
  d["radius"] = values(g.spheres, [](const api::Sphere& s) { return s.radius; });
}
void curve_arrays(pyb::dict& d, const api::GeometryData& g) {
  pyb::array_t<float> p(std::vector<pyb::ssize_t>{static_cast<pyb::ssize_t>(g.curves.size()), 4, 3});
  float* out = p.mutable_data();
  for (const api::Curve& c : g.curves)
    for (const Vec3& v : c.p) *out++ = v.x, *out++ = v.y, *out++ = v.z;
  d["points"] = p;
  d["radius"] = values(g.curves, [](const api::Curve& c) { return c.radius; });
  d["tangents"] = points(g.curves, curve_tangent);
  add_strands(d, g);
}

void ribbon_arrays(pyb::dict& d, const api::GeometryData& g) {
  d["p0"] = points(g.ribbons, [](const api::Ribbon& r) { return r.p0; });
  d["r0"] = values(g.ribbons, [](const api::Ribbon& r) { return r.r0; });
  d["p1"] = points(g.ribbons, [](const api::Ribbon& r) { return r.p1; });
  d["r1"] = values(g.ribbons, [](const api::Ribbon& r) { return r.r1; });
  d["normal"] = points(g.ribbons, [](const api::Ribbon& r) { return r.n; });
  d["tangents"] = points(g.ribbons, [](const api::Ribbon& r) { return unit_from(r.p0, r.p1); });
  add_strands(d, g);
}

// One row per primitive type (GeometryData::type names it): the arrays its dict holds,
// the names add_* takes, so that scene.add_capsules(**{k: d[k] for k in ("a", "b",
// "radius")}) rebuilds it.
struct GeometryRow {
  const char* type;
  void (*arrays)(pyb::dict&, const api::GeometryData&);
};
constexpr GeometryRow geometry_rows[] = {
    {"triangle", triangle_arrays}, {"capsule", capsule_arrays}, {"round_cone", round_cone_arrays},
    {"sphere", sphere_arrays},     {"curve", curve_arrays},         {"ribbon", ribbon_arrays},
};

pyb::dict geometry(const api::Scene& scene, long id) {
  if (id < 0 || static_cast<std::size_t>(id) >= scene.geometry_count())
    throw pyb::index_error("Scene.geometry: id: geometry " + std::to_string(id) + " does not exist (the scene has " +
                           std::to_string(scene.geometry_count()) + ")");
  const api::GeometryData g = scene.geometry(static_cast<std::uint32_t>(id));
  for (const GeometryRow& row : geometry_rows)
    if (g.type == row.type) {
      pyb::dict d;
      d["type"] = g.type;
      row.arrays(d, g);
      return d;
    }
  throw Error("Scene.geometry: no Python row for primitive type '" + g.type + "' (python/src/bind_scene.cpp)");
}

// ---- cameras

api::Vec3d vec3d(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }
pyb::array_t<double> numpy3(const api::Vec3d& v) {
  pyb::array_t<double> a(3);
  a.mutable_data()[0] = v.x, a.mutable_data()[1] = v.y, a.mutable_data()[2] = v.z;
  return a;
}

// ValueError naming the argument for a camera that makes no image: eye on the target,
// up along the view, a field of view outside (0, 180) degrees.
void check_camera(const api::Camera& c, const char* function) {
  const double f[3] = {c.target.x - c.eye.x, c.target.y - c.eye.y, c.target.z - c.eye.z};
  if (f[0] == 0 && f[1] == 0 && f[2] == 0)
    throw pyb::value_error(std::string(function) + ": target: equals eye (no view direction)");
  const double u[3] = {c.up.x, c.up.y, c.up.z};
  const double cross[3] = {f[1] * u[2] - f[2] * u[1], f[2] * u[0] - f[0] * u[2], f[0] * u[1] - f[1] * u[0]};
  if (cross[0] == 0 && cross[1] == 0 && cross[2] == 0)
    throw pyb::value_error(std::string(function) + ": up: zero or parallel to the view direction (target - eye)");
  if (!c.orthographic && !(c.fov_y_deg > 0 && c.fov_y_deg < 180))
    throw pyb::value_error(std::string(function) + ": fov: " + std::to_string(c.fov_y_deg) +
                           " degrees (the vertical field of view must be in (0, 180))");
}

void check_image(int width, int height, const char* function) {
  if (width <= 0 || height <= 0)
    throw pyb::value_error(std::string(function) + ": width and height must be positive, got " +
                           std::to_string(width) + " x " + std::to_string(height));
}

pyb::array camera_rays(const api::Camera& c, int width, int height, const char* function) {
  check_image(width, height, function);
  check_camera(c, function);
  std::vector<api::Ray> rays;
  {
    pyb::gil_scoped_release unlocked;
    rays = api::camera_rays(c, width, height);
  }
  return rays_to_numpy(rays);
}

// The scene's camera with what is given replaced; a given fov makes it a pinhole.
pyb::array scene_camera_rays(const api::Scene& scene, int width, int height, const OptionalArrayLike& eye,
                             const OptionalArrayLike& target, const OptionalArrayLike& up, std::optional<double> fov) {
  const char* f = "Scene.camera_rays";
  check_image(width, height, f);
  api::Camera c = scene.camera();
  if (!eye.is_none()) c.eye = vec3d(vec3_arg(eye, {f, "eye"}));
  if (!target.is_none()) c.target = vec3d(vec3_arg(target, {f, "target"}));
  if (!up.is_none()) c.up = vec3d(vec3_arg(up, {f, "up"}));
  if (fov) {
    c.fov_y_deg = *fov;
    c.orthographic = false;
  }
  return camera_rays(c, width, height, f);
}

pyb::array pinhole_rays(int width, int height, const ArrayLike& eye, const ArrayLike& target,
                        const ArrayLike& up, double fov) {
  const char* f = "pinhole_rays";
  api::Camera c;
  c.eye = vec3d(vec3_arg(eye, {f, "eye"}));
  c.target = vec3d(vec3_arg(target, {f, "target"}));
  c.up = vec3d(vec3_arg(up, {f, "up"}));
  c.fov_y_deg = fov;
  return camera_rays(c, width, height, f);
}

pyb::dict camera_dict(const api::Scene& scene) {
  const api::Camera c = scene.camera();
  pyb::dict d;
  d["eye"] = numpy3(c.eye);
  d["target"] = numpy3(c.target);
  d["up"] = numpy3(c.up);
  d["fov"] = c.fov_y_deg;
  d["orthographic"] = c.orthographic;
  d["ortho_height"] = c.ortho_height;
  return d;
}

pyb::array_t<double> bounds(const api::Scene& scene) {
  const api::Box b = scene.bounds();
  pyb::array_t<double> out(std::vector<pyb::ssize_t>{2, 3});
  double* p = out.mutable_data();
  for (const api::Vec3d& v : {b.lower, b.upper}) *p++ = v.x, *p++ = v.y, *p++ = v.z;
  return out;
}

std::uint32_t add_instance(api::Scene& scene, std::uint32_t geometry, const OptionalArrayLike& transform) {
  api::Transform t;
  if (!transform.is_none()) {
    pyb::array a = pyb::isinstance<pyb::array>(transform) ? pyb::reinterpret_borrow<pyb::array>(transform)
                                                          : pyb::array(pyb::module_::import("numpy").attr("asarray")(transform));
    if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 4)
      throw pyb::value_error("Scene.add_instance: transform: expected a 3x4 object-to-world matrix (rows: x, y, z; "
                             "columns: the linear part, then the translation)");
    if (a.dtype().kind() != 'f' && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
      throw pyb::type_error("Scene.add_instance: transform: expected a float array, got dtype " +
                            pyb::str(a.dtype()).cast<std::string>());
    // 12 values: any layout may be read (a copy to float64 is made either way).
    auto d = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(a);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        const double v = d.data()[4 * r + c];
        if (!std::isfinite(v))
          throw pyb::value_error("Scene.add_instance: transform: element [" + std::to_string(r) + ", " +
                                 std::to_string(c) + "] is not finite");
        t.m[r][c] = v;
      }
  }
  return scene.add_instance(geometry, t);
}

} // namespace

void bind_scene(pyb::module_& m) {
  m.def("pinhole_rays", &pinhole_rays, pyb::arg("width"), pyb::arg("height"), pyb::arg("eye"), pyb::arg("target"),
        pyb::arg("up") = pyb::make_tuple(0.0, 1.0, 0.0), pyb::arg("fov") = 40.0,
        "Primary rays of a pinhole camera at eye looking at target (fov: vertical, degrees) as a flat "
        "masq.ray_dtype array of width * height unit-length rays, row-major from the top.");
  pyb::class_<api::Scene>(m, "Scene", R"(An in-memory scene: geometries (arrays of one primitive type each) placed by
instances. A scene without instances places every geometry once, untransformed. Input is
checked when added (arrays) and when an Accel is built (topology, degenerate transforms).)")
      .def(pyb::init<>())
      .def_static(
          "load",
          [](const std::filesystem::path& path, float radius, bool round_cones) {
            // The loader's repairs (negative radii made positive, a default radius) reach
            // Python as warnings.warn, raised once the GIL is held again.
            std::vector<std::string> notes;
            api::LoadOptions options{radius, round_cones, [&notes](const std::string& line) { notes.push_back(line); }};
            api::Scene scene = [&] {
              pyb::gil_scoped_release unlocked;
              return api::Scene::load(path.string(), options);
            }();
            if (!notes.empty()) {
              auto warn = pyb::module_::import("warnings").attr("warn");
              for (const std::string& line : notes) warn(line, pyb::handle(load_warning()), 2);
            }
            return scene;
          },
          pyb::arg("path"), pyb::arg("radius") = 0.0f, pyb::arg("round_cones") = false,
          "Reads a scene file (a str or os.PathLike) chosen by its extension (Scene.file_extensions()). radius: "
          "for strands whose file has none (0: the loader's default; negative: an error); round_cones: strands as "
          "round cones instead of capsules. Each repair the loader makes is a masq.LoadWarning.")
      .def_static("file_extensions", &api::Scene::file_extensions)
      .def("add_triangles", &add_triangles, pyb::arg("vertices"), pyb::arg("indices"),
           "vertices: (n, 3) floats; indices: (m, 3) integers. Returns the geometry id.")
      .def("add_capsules", &add_capsules, pyb::arg("a"), pyb::arg("b"), pyb::arg("radius"),
           "a, b: (n, 3) end points; radius: a number or (n,) radii. Returns the geometry id.")
      .def("add_round_cones", &add_round_cones, pyb::arg("a"), pyb::arg("ra"), pyb::arg("b"), pyb::arg("rb"),
           "a, b: (n, 3) end points; ra, rb: their radii (numbers or (n,)). Returns the geometry id.")
      .def("add_spheres", &add_spheres, pyb::arg("centers"), pyb::arg("radius"),
           "centers: (n, 3); radius: a number or (n,). Returns the geometry id.")
      .def("add_curves", &add_curves, pyb::arg("points"), pyb::arg("radius"),
           "points: (n, 4, 3) cubic Bezier control points; radius: a number or (n,). Returns the geometry id.")
      .def("add_ribbons", &add_ribbons, pyb::arg("p0"), pyb::arg("r0"), pyb::arg("p1"), pyb::arg("r1"),
           pyb::arg("normal"),
           "Flat ribbons facing `normal`: p0, p1, normal: (n, 3); r0, r1: half-widths at p0 and p1 (numbers or "
           "(n,)). The strip runs along normalize(cross(normal, p1 - p0)). Returns the geometry id.")
      .def("add_instance", &add_instance, pyb::arg("geometry"), pyb::arg("transform") = pyb::none(),
           "Places geometry with a 3x4 object-to-world transform (None: identity). Returns the instance id.")
      .def_property_readonly("geometry_count", &api::Scene::geometry_count)
      .def_property_readonly("instance_count", &api::Scene::instance_count)
      .def_property_readonly("primitive_count", &api::Scene::primitive_count)
      .def("validate", &api::Scene::validate, "Raises masq.Error naming the first bad element.")
      .def("geometry", &geometry, pyb::arg("id"),
           "Geometry `id` read back (object space) as a dict of numpy arrays: 'type' (triangle, capsule, round_cone, "
           "sphere, curve, ribbon) and its type's arrays under add_*'s names (triangle: vertices, indices; capsule: a, "
           "b, radius; round_cone: a, ra, b, rb; sphere: centers, radius; curve: points (n, 4, 3), radius; ribbon: "
           "p0, r0, p1, r1, normal). Types "
           "with an axis add 'tangents' (n, 3) (unit b - a; a curve's at its middle) and 'strands' (n,) int32: "
           "the strand of each primitive, numbered in order, primitive i + 1 continuing i's strand when it starts "
           "where i ends (as the strand loaders write them).")
      .def_property_readonly("bounds", &bounds,
                             "numpy.ndarray: world-space box of the placed scene, radii included, as a (2, 3) "
                             "float64 array: lower, upper (lo, hi = scene.bounds). A curve is bounded by its control "
                             "points' balls. An empty scene: +inf, -inf.")
      .def_property_readonly("camera", &camera_dict,
                             "dict: the camera camera_rays uses, the file's, else a view framing the scene: eye, "
                             "target, up ((3,) float64), fov (vertical, degrees), orthographic, ortho_height.")
      .def("camera_rays", &scene_camera_rays, pyb::arg("width"), pyb::arg("height"), pyb::arg("eye") = pyb::none(),
           pyb::arg("target") = pyb::none(), pyb::arg("up") = pyb::none(), pyb::arg("fov") = pyb::none(),
           "Primary rays (row-major from the top: reshape(height, width) for an image-shaped trace) as a flat "
           "masq.ray_dtype array of width * height rays. The camera is the scene's (Scene.camera: the file's, "
           "else a view framing the scene from -z) with each of eye, target, up ((3,) points) and fov (vertical, "
           "degrees) that is given replaced; a given fov makes it a pinhole. Pass it to Context.trace as it is "
           "(no copy).")
      .def("__repr__", [](const api::Scene& s) {
        return "<masq.Scene " + std::to_string(s.geometry_count()) + " geometries, " +
               std::to_string(s.instance_count()) + " instances, " + std::to_string(s.primitive_count()) +
               " primitives>";
      });
}

} // namespace masq::py
