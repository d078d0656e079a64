// NFF (Neutral File Format) loader, as written by Eric Haines' SPD 3.14 generators, and
// classic NFF. The input is tokenised on whitespace, so a cone/cylinder `c` may be on one
// line (SPD 3.14) or on three (classic: `c`, base line, apex line).
//
//  - `s x y z r`                 -> SpherePrim (geometry of spheres)
//  - `c bx by bz br ax ay az ar` -> RoundConePrim {base, br, apex, ar}. The NFF cone is
//    a truncated cone without caps; masq has no such primitive and represents it as a
//    round cone (the convex hull of the two end spheres), the closest primitive it has.
//    Equal radii (NFF cylinders) are round cones too (a capsule shape), so one `c` line
//    always gives one primitive of the same geometry.
//  - `p n` + n lines `x y z`     -> triangles, fan-triangulated (n >= 3)
//  - `pp n` + n lines `x y z nx ny nz` -> same, normals ignored
//  - `v`, `from`, `at`, `up`, `angle`, `hither`, `resolution` -> Scene::camera
//    (eye, target, up, fov_y_deg = angle; hither and resolution are checked and ignored)
//  - `b`, `l`, `f` (background, light, fill): numbers checked, otherwise ignored
//  - `#` starts a comment line.
// The scene holds up to three geometries, in this order: spheres, round cones,
// triangles (only the non-empty ones), each instanced once with the identity.
// Repairs (via LoadOptions::warn): a negative radius is made positive. Everything else
// that is wrong throws masq::Error naming the source and the line: unknown keywords,
// missing or non-numeric values, NaN/Inf, polygons with fewer than 3 vertices,
// truncated files, and a file without primitives.
#pragma once
#include "scenes/loaders/loader.h"

namespace masq {

Scene load_nff(const std::string& path, const LoadOptions& opt = {});
Scene load_nff(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt = {});

} // namespace masq
