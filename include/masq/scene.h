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
  /// Places geometry `geometry` with `object_to_world`. Returns the instance id.
  /// Throws masq::Error for an unknown geometry id.
  std::uint32_t add_instance(std::uint32_t geometry, const Transform& object_to_world = Transform::identity());

  std::size_t geometry_count() const;
  std::size_t instance_count() const;
  /// The primitives an Accel of this scene traces: each instance counts its geometry's
  /// (a scene without instances: each geometry's once).
  std::size_t primitive_count() const;

  /// Throws masq::Error naming the first bad element; see the class comment.
  void validate() const;

  /// Primary rays (row-major from the top) of the scene's camera: the file's camera for
  /// scenes loaded with one, else a view framing the whole scene from -z.
  std::vector<Ray> camera_rays(int width, int height) const;

  struct Impl;
  /// Internal; for the library's own use.
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

} // namespace masq::api
