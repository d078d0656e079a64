// masq.Scene: scenes from files and from numpy arrays. Each add_* checks its arrays
// (arrays.h) and packs them into the public API's primitive structs; the Scene copies
// them in, so the caller's arrays may change afterwards.
#include "arrays.h"
#include "bindings.h"
#include "masq/scene.h"
#include <cmath>
#include <filesystem>
#include <pybind11/stl/filesystem.h>
#include <cstring>

namespace masq::py {

namespace {

using api::Vec3;

Vec3 vec3_at(const float* p) { return {p[0], p[1], p[2]}; }

std::uint32_t add_triangles(api::Scene& scene, const pyb::handle& vertices, const pyb::handle& indices) {
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

std::uint32_t add_capsules(api::Scene& scene, const pyb::handle& a, const pyb::handle& b, const pyb::handle& radius) {
  auto pa = float_rows(a, {"Scene.add_capsules", "a"}, 3);
  auto pb = float_rows(b, {"Scene.add_capsules", "b"}, 3, static_cast<long>(row_count(pa)));
  PerRowFloat r = per_row_float(radius, {"Scene.add_capsules", "radius"}, row_count(pa));
  std::vector<api::Capsule> caps(row_count(pa));
  for (std::size_t i = 0; i < caps.size(); ++i) caps[i] = {vec3_at(pa.data() + 3 * i), vec3_at(pb.data() + 3 * i), r[i]};
  return scene.add_capsules(caps);
}

std::uint32_t add_round_cones(api::Scene& scene, const pyb::handle& a, const pyb::handle& ra, const pyb::handle& b,
                              const pyb::handle& rb) {
  auto pa = float_rows(a, {"Scene.add_round_cones", "a"}, 3);
  const std::size_t n = row_count(pa);
  auto pb = float_rows(b, {"Scene.add_round_cones", "b"}, 3, static_cast<long>(n));
  PerRowFloat r0 = per_row_float(ra, {"Scene.add_round_cones", "ra"}, n);
  PerRowFloat r1 = per_row_float(rb, {"Scene.add_round_cones", "rb"}, n);
  std::vector<api::RoundCone> round_cones(n);
  for (std::size_t i = 0; i < n; ++i) round_cones[i] = {vec3_at(pa.data() + 3 * i), r0[i], vec3_at(pb.data() + 3 * i), r1[i]};
  return scene.add_round_cones(round_cones);
}

std::uint32_t add_spheres(api::Scene& scene, const pyb::handle& centers, const pyb::handle& radius) {
  auto c = float_rows(centers, {"Scene.add_spheres", "centers"}, 3);
  PerRowFloat r = per_row_float(radius, {"Scene.add_spheres", "radius"}, row_count(c));
  std::vector<api::Sphere> spheres(row_count(c));
  for (std::size_t i = 0; i < spheres.size(); ++i) spheres[i] = {vec3_at(c.data() + 3 * i), r[i]};
  return scene.add_spheres(spheres);
}

std::uint32_t add_curves(api::Scene& scene, const pyb::handle& points, const pyb::handle& radius) {
  auto p = float_blocks(points, {"Scene.add_curves", "points"}, 4, 3);
  PerRowFloat r = per_row_float(radius, {"Scene.add_curves", "radius"}, row_count(p));
  std::vector<api::Curve> curves(row_count(p));
  for (std::size_t i = 0; i < curves.size(); ++i) {
    for (int k = 0; k < 4; ++k) curves[i].p[k] = vec3_at(p.data() + 12 * i + 3 * k);
    curves[i].radius = r[i];
  }
  return scene.add_curves(curves);
}

std::uint32_t add_instance(api::Scene& scene, std::uint32_t geometry, const pyb::handle& transform) {
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
      .def("add_instance", &add_instance, pyb::arg("geometry"), pyb::arg("transform") = pyb::none(),
           "Places geometry with a 3x4 object-to-world transform (None: identity). Returns the instance id.")
      .def_property_readonly("geometry_count", &api::Scene::geometry_count)
      .def_property_readonly("instance_count", &api::Scene::instance_count)
      .def_property_readonly("primitive_count", &api::Scene::primitive_count)
      .def("validate", &api::Scene::validate, "Raises masq.Error naming the first bad element.")
      .def(
          "camera_rays",
          [](const api::Scene& scene, int width, int height) {
            if (width <= 0 || height <= 0)
              throw pyb::value_error("Scene.camera_rays: width and height must be positive, got " +
                                     std::to_string(width) + " x " + std::to_string(height));
            return rays_to_numpy(scene.camera_rays(width, height));
          },
          pyb::arg("width"), pyb::arg("height"),
          "Primary rays of the scene's camera (row-major from the top) as a masq.ray_dtype array: the file's "
          "camera, else a view framing the scene from -z. Pass it to Context.trace as it is (no copy).")
      .def("__repr__", [](const api::Scene& s) {
        return "<masq.Scene " + std::to_string(s.geometry_count()) + " geometries, " +
               std::to_string(s.instance_count()) + " instances, " + std::to_string(s.primitive_count()) +
               " primitives>";
      });
}

} // namespace masq::py
