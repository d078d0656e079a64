#include "cli/scene_options.h"
#include "scenes/prim_table.h"
#include "scenes/curve_tools.h"
#include "scenes/loaders/load_any.h"
#include "masq/error.h"
#include <algorithm>
#include <cstdio>

namespace masq::cli {

void add_scene_options(CLI::App& cmd, SceneOptions& opt) {
  cmd.add_option("--scene", opt.scene, "Embedded scene: " + embedded_scene_table.help())
      ->capture_default_str()
      ->check(CLI::IsMember(embedded_scene_table.names()));
  cmd.add_option("--file", opt.file,
                 "Scene file instead of --scene: .tfx (TressFX 3/4), .hair, .swc, .trk, .tck, .ply, .obj, .nff, .json (scene "
                 "description); strands use --prim capsule, round_cone or curve (Catmull-Rom through the points)");
  cmd.add_option("--file-radius", opt.file_radius, "Strand radius where the file has none (0: the loader's default)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--strands", opt.strands, "hair, fur, streamlines: number of strands")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000000));
  cmd.add_option("--count", opt.bundle.count, "Strands in the default bundle scene")->capture_default_str()->check(CLI::PositiveNumber);
  cmd.add_option("--radius", opt.bundle.radius, "Strand radius")->capture_default_str()->check(CLI::PositiveNumber);
  cmd.add_option("--tilt", opt.bundle.tilt_deg, "Bundle tilt in degrees (X-Y plane)")->capture_default_str();
  cmd.add_option("--seed", opt.bundle.seed, "Random seed of the bundle")->capture_default_str();
  // Strands are thin primitives: every type but the mesh.
  auto strand = [](const PrimTypeRow& r) { return !scene_prim_row(r.value).mesh; };
  cmd.add_option("--prim", opt.prim,
                 "Strand primitive: " + prim_type_table.help(strand) +
                     "; the bundle's round cones taper from r to r/2, its curves bend and its spheres are beads")
      ->capture_default_str()
      ->check(CLI::IsMember(prim_type_table.accepted_names(strand)));
  cmd.add_option("--subdiv", opt.subdivisions, "Curves: pre-subdivide each cubic into k pieces (1, 2, 4, 8...)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd.add_flag("--ortho", opt.orthographic, "Orthographic view along +z from z=-5 (the paper's setup)");
  cmd.add_option("--mode", opt.mode, "Intersectors and masquerade box test: " + mode_table.help())
      ->capture_default_str()
      ->check(CLI::IsMember(mode_table.names()));
  cmd.add_option("--curve-obb", opt.curve_obb, "Curve OBBs: " + curve_obb_table.help())
      ->capture_default_str()
      ->check(CLI::IsMember(curve_obb_table.names()));
  cmd.add_option("--curve-iters", opt.curve_iters, "Phantom curve iteration limit")->capture_default_str()->check(CLI::Range(1, 64));
  cmd.add_option("--curve-isect", opt.curve_isects,
                 "Cubic-curve intersector: " + curve_isect_table.help() + "; bench takes a comma-separated list and runs each")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember(curve_isect_table.names()));
  cmd.add_option("--cluster-size", opt.cluster_size, "Methods cluster/auto: most primitives per oriented cluster")
      ->capture_default_str()
      ->check(CLI::Range(2, 256));
  cmd.add_option("--cluster-classes", opt.cluster_classes, "Methods cluster/auto: orientation classes (hemisphere bins)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  cmd.add_option("--cluster-leaf-price", opt.cluster_leaf_price,
                 "Method cluster: SAH price of a cluster BLAS node visit in intersector calls (1: one member per leaf, "
                 "fewest calls; 4: full leaves, fewer bytes); auto tries 1 and this (docs/methods.md)")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 64.0));
  cmd.add_option("--nodes", opt.nodes,
                 "BVH node format of the TLAS and every BLAS: " + node_format_table.help() +
                     "; bench takes a comma-separated list and runs each")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember(node_format_table.names()));
  cmd.add_option("--masq-instance", opt.masq_instance,
                 "Masquerade TLAS entries: " + masq_instances_table.help() + "; docs/kernels.md")
      ->capture_default_str()
      ->check(CLI::IsMember(masq_instances_table.names()));
  cmd.add_option("--blas-occlusion", opt.blas_occlusion,
                 "Occlusion queries' order over a BLAS node's hit inner children: " + blas_occlusion_table.help() +
                     "; the same rays occluded either way (docs/kernels.md, Occlusion order)")
      ->capture_default_str()
      ->check(CLI::IsMember(blas_occlusion_table.names()));
  cmd.add_option("--prices", opt.prices, "Method auto: cost-model prices NODE TRANSFORM ISECT (default 1 1.5 2.5; docs/methods.md)")
      ->expected(3)
      ->check(CLI::PositiveNumber);
  cmd.add_option("--builder", opt.builders,
                 "Binary BVH builder: " + builder_table.help() +
                     "; bench takes a comma-separated list and runs each side by side (docs/builders.md)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember(builder_table.names()));
  cmd.add_option("--build-threads", opt.build_threads,
                 "Threads of the host BVH build: 0 every hardware thread, 1 serial; the structure is the same with "
                 "any count (docs/builders.md)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--sbvh-budget", opt.sbvh_budget, "sbvh: at most this many BLAS references per primitive (>= 1)")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 64.0));
  cmd.add_option("--sbvh-alpha", opt.sbvh_alpha,
                 "sbvh: try spatial splits where the object split's children overlap by more than this fraction of "
                 "the root area")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
}

Scene make_scene(const SceneOptions& opt) {
  PrimType prim = parse_prim_type(opt.prim);
  const ScenePrimRow& row = scene_prim_row(prim);
  if (!opt.file.empty()) {
    LoadOptions lo;
    lo.radius = opt.file_radius;
    // Curves: the strands are loaded as round cones (keeping per-point radii) and
    // turned into Catmull-Rom cubics through the same points.
    lo.strand_type = row.strand_file_type;
    lo.warn = [](const std::string& w) { std::fprintf(stderr, "masq: warning: %s\n", w.c_str()); };
    Scene s = load_scene_file(opt.file, lo);
    if (row.shape == PrimShape::Bezier) s = subdivide_curves(segments_to_curves(s), opt.subdivisions);
    return s;
  }
  const EmbeddedScene embedded = embedded_scene_table.parse(opt.scene);
  if (embedded == EmbeddedScene::Hair || embedded == EmbeddedScene::Fur) {
    HairParams hp;
    hp.strands = opt.strands;
    hp.surface = embedded == EmbeddedScene::Fur ? HairSurface::Body : HairSurface::Head;
    if (embedded == EmbeddedScene::Fur) {
      hp.points = 4;
      hp.length = 0.15;
      hp.gravity = 0.1;
    }
    // A strand grows along an axis: a type without one (the sphere) gets the hair's curves.
    hp.type = row.oriented ? prim : PrimType::Curve;
    hp.seed = opt.bundle.seed;
    return subdivide_curves(make_hair_scene(hp), opt.subdivisions);
  }
  if (embedded == EmbeddedScene::Streamlines) {
    StreamlineParams sp;
    sp.lines = opt.strands;
    // A type without an axis (the sphere) gets the streamlines' round cones.
    sp.type = row.oriented ? prim : PrimType::RoundCone;
    sp.seed = opt.bundle.seed;
    return subdivide_curves(make_streamline_scene(sp), opt.subdivisions);
  }
  BundleParams bp = opt.bundle;
  bp.prim = prim;
  Scene s = subdivide_curves(make_default_scene(bp), opt.subdivisions);
  if (opt.orthographic) {
    s.camera.eye = {0.0, 0.0, -5.0};
    s.camera.target = {0.0, 0.0, 0.0};
    s.camera.orthographic = true;
    s.camera.ortho_height = 1.8;
  }
  return s;
}

namespace {
// A list option's names as values of its table: each once, at least one.
template <class T, class Table>
std::vector<T> parse_unique(const std::vector<std::string>& names, const Table& table, const std::string& option) {
  std::vector<T> out;
  for (const std::string& n : names) {
    T v = table.parse(n);
    if (std::find(out.begin(), out.end(), v) != out.end()) throw Error(option + ": '" + n + "' is given twice");
    out.push_back(v);
  }
  if (out.empty()) throw Error(option + ": none given (expected " + table.choices() + ")");
  return out;
}
} // namespace

std::vector<CurveIsect> curve_isects(const SceneOptions& opt) {
  return parse_unique<CurveIsect>(opt.curve_isects, curve_isect_table, "--curve-isect");
}

std::vector<NodeFormat> node_formats(const SceneOptions& opt) {
  return parse_unique<NodeFormat>(opt.nodes, node_format_table, "--nodes");
}

AccelOptions accel_options(const SceneOptions& opt) {
  AccelOptions a;
  a.nodes = node_formats(opt).front();
  a.mode = parse_mode(opt.mode);
  a.curve_obb = parse_curve_obb(opt.curve_obb);
  a.curve_iters = opt.curve_iters;
  a.curve_isect = curve_isects(opt).front();
  a.masq_instances = parse_masq_instances(opt.masq_instance);
  a.blas_occlusion = parse_blas_occlusion(opt.blas_occlusion);
  a.cluster.max_size = opt.cluster_size;
  a.cluster.classes = opt.cluster_classes;
  a.cluster.leaf_price = opt.cluster_leaf_price;
  if (opt.prices.size() == 3) a.prices = {opt.prices[0], opt.prices[1], opt.prices[2]};
  std::vector<Builder> builders = parse_builders(opt);
  a.builder.kind = builders.empty() ? Builder::Sah : builders.front();
  a.builder.sbvh.max_refs = opt.sbvh_budget;
  a.builder.sbvh.alpha = opt.sbvh_alpha;
  a.build_threads = opt.build_threads;
  return a;
}

std::vector<Builder> parse_builders(const SceneOptions& opt) {
  std::vector<Builder> out;
  for (const std::string& name : opt.builders) {
    Builder b = parse_builder(name);
    if (std::find(out.begin(), out.end(), b) == out.end()) out.push_back(b);
  }
  return out;
}

} // namespace masq::cli
