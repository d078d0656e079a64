/// @file masq/scene.h
/// A scene: geometries (arrays of one primitive type each) placed by instances.
#pragma once
#include "masq/types.h"
#include <functional>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace masq::api {

/// How a scene file is read (Scene::load).
struct LoadOptions {
  /// Radius for strands whose file has none (or the scale of a file's relative
  /// thickness); 0: the loader's default. Negative or not finite: Scene::load throws.
  float radius = 0.0f;
  bool round_cones = false;   ///< strands as round cones (radius interpolated) instead of capsules
  /// Receives one line for each repair or assumption the loader made (negative SWC radii
  /// made positive, a default radius chosen, bytes after the data ignored). Empty: the
  /// repairs are made all the same, silently.
  std::function<void(const std::string&)> warn;
};

/// A point or direction in double precision (cameras and bounds, which the library
/// computes in double).
struct Vec3d {
  double x = 0, y = 0, z = 0;
};

/// A camera: a pinhole with a vertical field of view, or orthographic with a view height
/// (Scene::camera, camera_rays).
struct Camera {
  Vec3d eye{0, 0, -5};
  Vec3d target{0, 0, 0};
  Vec3d up{0, 1, 0};
  double fov_y_deg = 40;      ///< pinhole: vertical field of view in degrees, in (0, 180)
  bool orthographic = false;
  double ortho_height = 2;    ///< orthographic: the view's height in world units
};

/// Primary rays of `camera` for a width x height image, row-major from the top (pixel
/// centres; pinhole rays unit length, from the eye). Throws masq::Error for an empty
/// image, an eye on the target, an up along the view, a field of view outside (0, 180)
/// or a non-finite value.
std::vector<Ray> camera_rays(const Camera& camera, int width, int height);

/// An axis-aligned box; lower > upper on every axis (+inf, -inf) when it holds nothing.
struct Box {
  Vec3d lower, upper;
};

/// One geometry read back (Scene::geometry): its primitive type's name and that type's
/// array; the arrays of the other types are empty.
struct GeometryData {
  std::string type; ///< "triangle", "capsule", "round_cone", "sphere", "curve" or "ribbon"
  std::vector<Vec3> vertices;          ///< triangles
  std::vector<std::uint32_t> indices;  ///< triangles: 3 vertex indices each
  std::vector<Capsule> capsules;
  std::vector<RoundCone> round_cones;
  std::vector<Sphere> spheres;
  std::vector<Curve> curves;
  std::vector<Ribbon> ribbons; ///< n as it was added (the kernels get it unit length)
  /// Types with an axis (capsules, round cones, curves, ribbons): the strand of each primitive,
  /// numbered from 0 in order. Primitive i + 1 is in primitive i's strand when it starts
  /// where i ends, as the strand loaders write a strand's segments. Other types: empty.
  std::vector<std::uint32_t> strands;
};

/// An in-memory scene. A value type: copies are deep, moves are cheap (a moved-from
/// Scene may only be assigned to or destroyed). Not thread-safe
/// for writing; const member functions may be called from several threads at once.
///
/// Geometries are added with add_triangles/add_capsules/...; each call makes one
/// geometry and returns its id. add_instance places a geometry with a transform. A scene
/// with geometries but no instances places every geometry once with the identity when an
/// Accel is built from it. Input is validated when the Accel is built (or by validate()):
/// out-of-range indices, NaN/Inf coordinates, negative radii, singular transforms and
/// empty scenes throw masq::Error naming the geometry and primitive.
class Scene {
 public:
  Scene();
  ~Scene();
  Scene(const Scene&);
  Scene& operator=(const Scene&);
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  /// Reads a scene file chosen by its extension: .tfx .hair .swc .trk .tck .ply .obj
  /// .nff or a .json scene description. Throws masq::Error naming the file and the
  /// byte offset or line of bad content.
  static Scene load(const std::string& path, const LoadOptions& options = {});
  /// The file extensions load() understands (".tfx", ".hair", ...).
  static std::vector<std::string> file_extensions();

  /// Triangles: indices holds 3 vertex indices per triangle. Returns the geometry id.
  std::uint32_t add_triangles(std::span<const Vec3> vertices, std::span<const std::uint32_t> indices);
  std::uint32_t add_capsules(std::span<const Capsule> capsules);
  std::uint32_t add_round_cones(std::span<const RoundCone> round_cones);
  std::uint32_t add_spheres(std::span<const Sphere> spheres);
  std::uint32_t add_curves(std::span<const Curve> curves);
  std::uint32_t add_ribbons(std::span<const Ribbon> ribbons);
  /// Places geometry `geometry` with `object_to_world`. Returns the instance id.
  /// Throws masq::Error for an unknown geometry id.
  std::uint32_t add_instance(std::uint32_t geometry, const Transform& object_to_world = Transform::identity());

  std::size_t geometry_count() const;
  /// A copy of geometry `id` as it was added or loaded (object space). Throws masq::Error
  /// for an unknown id.
  GeometryData geometry(std::uint32_t id) const;
  std::size_t instance_count() const;
  /// The primitives an Accel of this scene traces: each instance counts its geometry's
  /// (a scene without instances: each geometry's once).
  std::size_t primitive_count() const;

  /// Throws masq::Error naming the first bad element; see the class comment.
  void validate() const;

  /// The world-space box of every primitive as an Accel places them (a scene without
  /// instances: every geometry once), radii included; a curve is bounded by its control
  /// points' balls, so the box may be a little larger than the curve. Empty scene: the
  /// empty Box.
  Box bounds() const;

  /// The scene's camera: the file's camera for scenes loaded with one, else a view
  /// framing the whole scene (bounds()) from -z and a little above.
  Camera camera() const;
  /// Primary rays (row-major from the top) of camera(): camera_rays(camera(), width, height).
  std::vector<Ray> camera_rays(int width, int height) const;

  struct Impl;
  /// Internal; for the library's own use.
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

} // namespace masq::api
