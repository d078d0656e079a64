#include "bench/peer_scenes.h"
#include "masq/error.h"
#include "scenes/curve_tools.h"
#include "scenes/generators.h"
#include "scenes/loaders/load_any.h"
#include <filesystem>
#include <fmt/format.h>
#include <glm/glm.hpp>

namespace masq {

std::vector<PeerScene> peer_scenes(bool quick) {
  std::vector<PeerScene> out;
  const std::pair<const char*, const char*> hair[] = {{"bear fur (TressFX 3)", "hair/tressfx3_bear.tfx"},
                                                      {"Ratboy mohawk (TressFX 4)", "hair/tressfx4_Ratboy_mohawk.tfx"}};
  for (const auto& [name, file] : hair) {
    if (quick && out.size() >= 2) break;
    for (bool curves : {false, true})
      for (bool thick : {false, true}) {
        if (quick && thick) continue;
        out.push_back({fmt::format("{}, {}{}", name, curves ? "curves" : "capsules",
                                   thick ? fmt::format(", r = {} x mean segment", kThickRadius) : ""),
                       file, curves, thick});
      }
  }
  out.push_back({"default bundle (N=1000 r=0.002 tilt 45 + ground)", ""});
  return out;
}

void thicken(Scene& scene) {
  double length = 0;
  std::size_t n = 0;
  for (const Geometry& g : scene.geometries) {
    for (const CapsulePrim& c : g.capsules) length += glm::length(glm::dvec3(c.b) - glm::dvec3(c.a)), ++n;
    for (const RoundConePrim& c : g.round_cones) length += glm::length(glm::dvec3(c.b) - glm::dvec3(c.a)), ++n;
  }
  if (n == 0) throw Error("peers: a scene to thicken has no segments");
  const float r = float(kThickRadius * length / double(n));
  for (Geometry& g : scene.geometries) {
    for (CapsulePrim& c : g.capsules) c.radius = r;
    for (RoundConePrim& c : g.round_cones) c.ra = c.rb = r;
  }
}

double mean_radius(const Scene& scene) {
  double sum = 0;
  std::size_t n = 0;
  for (const Geometry& g : scene.geometries) {
    for (const CapsulePrim& c : g.capsules) sum += c.radius, ++n;
    for (const RoundConePrim& c : g.round_cones) sum += 0.5 * (double(c.ra) + double(c.rb)), ++n;
    for (const CurvePrim& c : g.curves) sum += c.radius, ++n;
  }
  return n ? sum / double(n) : 0.0;
}

Scene shape_peer_scene(Scene scene, bool curves, bool thick) {
  if (thick) thicken(scene);
  return curves ? segments_to_curves(scene) : scene;
}

Scene load_peer_file(const std::string& path, bool curves, bool thick) {
  // The cubics of table1's phantom x1 (bench/suite_hair.cpp make_case): the strands as
  // round cones, chained into Catmull-Rom curves through their points, one Bezier piece
  // per segment. Embree gets these very fp32 control points (embree_peer.cpp).
  LoadOptions lo;
  if (curves) lo.strand_type = PrimType::RoundCone;
  return shape_peer_scene(load_scene_file(path, lo), curves, thick);
}

Scene load_peer_scene(const SuiteConfig& cfg, const PeerScene& ps) {
  if (ps.file.empty()) return make_default_scene();
  return load_peer_file((std::filesystem::path(cfg.data_dir) / ps.file).string(), ps.curves, ps.thick);
}

} // namespace masq
