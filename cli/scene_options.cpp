#include "cli/scene_options.h"
#include "scenes/curve_tools.h"
#include "scenes/loaders/load_any.h"
#include "scenes/error.h"
#include <algorithm>
#include <cstdio>

namespace masq::cli {

void add_scene_options(CLI::App& cmd, SceneOptions& opt) {
  cmd.add_option("--scene", opt.scene,
                 "Embedded scene: bundle (the masquerade paper's), hair (on a head), fur (on a body), streamlines (ABC flow)")
      ->capture_default_str()
      ->check(CLI::IsMember({"bundle", "hair", "fur", "streamlines"}));
  cmd.add_option("--file", opt.file,
                 "Scene file instead of --scene: .tfx (TressFX 3/4), .hair, .swc, .trk, .tck, .ply, .obj, .nff, .json (scene "
                 "description); strands use --prim capsule, cone or curve (Catmull-Rom through the points)");
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
  cmd.add_option("--prim", opt.prim, "Strand primitive: capsule, cone (round cone r..r/2), curve (bent cubic), sphere (beads)")
      ->capture_default_str()
      ->check(CLI::IsMember({"capsule", "cone", "curve", "sphere"}));
  cmd.add_option("--subdiv", opt.subdivisions, "Curves: pre-subdivide each cubic into k pieces (1, 2, 4, 8...)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd.add_flag("--ortho", opt.orthographic, "Orthographic view along +z from z=-5 (the paper's setup)");
  cmd.add_option("--mode", opt.mode, "Intersectors and masquerade box test: robust (fp32-hardened, conservative) or fast (as published)")
      ->capture_default_str()
      ->check(CLI::IsMember({"robust", "fast"}));
  cmd.add_option("--curve-obb", opt.curve_obb, "Curve OBBs: paper (chord axis, cylinder) or tight (control-polygon fit)")
      ->capture_default_str()
      ->check(CLI::IsMember({"paper", "tight"}));
  cmd.add_option("--curve-iters", opt.curve_iters, "Phantom curve iteration limit")->capture_default_str()->check(CLI::Range(1, 64));
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
                 "BVH node format of the TLAS and every BLAS: w4 (4-wide float boxes), w8 (8-wide float boxes) or q8 "
                 "(8-wide, boxes quantised to 8 bits per plane); bench takes a list (w4,w8,q8) and runs each")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember({"w4", "w8", "q8"}));
  cmd.add_option("--masq-instance", opt.masq_instance,
                 "Masquerade TLAS entries: compact (32 bytes: quaternion, bfloat16 scales, owner index) or full (the "
                 "64-byte instance of RT hardware); docs/kernels.md")
      ->capture_default_str()
      ->check(CLI::IsMember({"compact", "full"}));
  cmd.add_option("--prices", opt.prices, "Method auto: cost-model prices NODE TRANSFORM ISECT (default 1 1.5 2.5; docs/methods.md)")
      ->expected(3)
      ->check(CLI::PositiveNumber);
  cmd.add_option("--builder", opt.builders,
                 "Binary BVH builder: sah (binned SAH, default), sbvh (spatial splits in every BLAS over primitives), "
                 "sah+reinsert or sbvh+reinsert (insertion optimisation of the TLAS and every BLAS), sah4 (binned SAH "
                 "pricing each BLAS leaf per block of four primitives: fuller leaves, for the cpu's four-lane capsule "
                 "test), sah-priced (binned SAH pricing each BLAS leaf primitive at its type's intersector cost: mostly "
                 "one-primitive leaves, fewer intersector calls, more nodes); bench takes a comma-separated list and runs each side by side (docs/builders.md)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember({"sah", "sbvh", "sah+reinsert", "sbvh+reinsert", "sah4", "sah-priced"}));
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
  if (!opt.file.empty()) {
    LoadOptions lo;
    lo.radius = opt.file_radius;
    // Curves: the strands are loaded as round cones (keeping per-point radii) and
    // turned into Catmull-Rom cubics through the same points.
    lo.strand_type = prim == PrimType::RoundCone || prim == PrimType::Curve ? PrimType::RoundCone : PrimType::Capsule;
    lo.warn = [](const std::string& w) { std::fprintf(stderr, "masq: warning: %s\n", w.c_str()); };
    Scene s = load_scene_file(opt.file, lo);
    if (prim == PrimType::Curve) s = subdivide_curves(segments_to_curves(s), opt.subdivisions);
    return s;
  }
  if (opt.scene == "hair" || opt.scene == "fur") {
    HairParams hp;
    hp.strands = opt.strands;
    hp.surface = opt.scene == "fur" ? HairSurface::Body : HairSurface::Head;
    if (opt.scene == "fur") {
      hp.points = 4;
      hp.length = 0.15;
      hp.gravity = 0.1;
    }
    hp.type = prim == PrimType::Sphere ? PrimType::Curve : prim;
    hp.seed = opt.bundle.seed;
    return subdivide_curves(make_hair_scene(hp), opt.subdivisions);
  }
  if (opt.scene == "streamlines") {
    StreamlineParams sp;
    sp.lines = opt.strands;
    sp.type = prim == PrimType::Sphere ? PrimType::RoundCone : prim;
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

std::vector<NodeFormat> node_formats(const SceneOptions& opt) {
  std::vector<NodeFormat> out;
  for (const std::string& n : opt.nodes) {
    NodeFormat f = parse_node_format(n);
    if (std::find(out.begin(), out.end(), f) != out.end()) throw Error("--nodes: '" + n + "' is given twice");
    out.push_back(f);
  }
  if (out.empty()) throw Error("--nodes: no node format given (expected w4, w8 or q8)");
  return out;
}

AccelOptions accel_options(const SceneOptions& opt) {
  AccelOptions a;
  a.nodes = node_formats(opt).front();
  a.mode = parse_mode(opt.mode);
  a.curve_obb = parse_curve_obb(opt.curve_obb);
  a.curve_iters = opt.curve_iters;
  a.masq_instances = parse_masq_instances(opt.masq_instance);
  a.cluster.max_size = opt.cluster_size;
  a.cluster.classes = opt.cluster_classes;
  a.cluster.leaf_price = opt.cluster_leaf_price;
  if (opt.prices.size() == 3) a.prices = {opt.prices[0], opt.prices[1], opt.prices[2]};
  std::vector<Builder> builders = parse_builders(opt);
  a.builder.kind = builders.empty() ? Builder::Sah : builders.front();
  a.builder.sbvh.max_refs = opt.sbvh_budget;
  a.builder.sbvh.alpha = opt.sbvh_alpha;
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
