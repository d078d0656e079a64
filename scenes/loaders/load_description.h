// Scene description files (.json): one file that combines scene files and generators,
// each with a transform, radius and primitive-type choices, and a camera, so a benchmark
// scene is one file.
//
//   {
//     "name": "bunny_and_bundle",                      // optional; default: file stem
//     "camera": {                                      // optional; default: frame_scene
//       "eye": [x, y, z], "target": [x, y, z],        // required in a camera
//       "up": [x, y, z],                               // optional, default [0, 1, 0]
//       "fov": deg,                                    // optional, default 40 (0 < fov < 180)
//       "ortho_height": h                              // optional; makes it orthographic
//     },
//     "objects": [ object, ... ]                       // required, at least one
//   }
//
// An object is a file or a generator:
//
//   {"file": path,
//    "radius": r,              // optional, LoadOptions::radius (> 0)
//    "prim": "capsule"|"round_cone", // optional, LoadOptions::strand_type ("cone" is read as "round_cone")
//    "subdiv": k,              // optional, subdivide_curves(k), k >= 1
//    "transform": T}           // optional
//
//   {"generator": "bundle", "count": n, "radius": r, "tilt": deg, "seed": s,
//                           "prim": "capsule"|"round_cone"|"curve"|"sphere"}       (BundleParams)
//   {"generator": "hair"|"fur", "strands": n, "points": n, "length": l, "radius": r,
//                           "curl": c, "seed": s, "prim": "capsule"|"round_cone"|"curve"}
//        (HairParams; hair grows on the head surface, fur on the body ellipsoid)
//   {"generator": "streamlines", "lines": n, "steps": n, "radius": r, "seed": s,
//                           "prim": "capsule"|"round_cone"|"curve"}           (StreamlineParams)
//   {"generator": "ground", "height": y, "size": half_side}  (make_ground_plane; default
//                           height 0, size 1)
//   Every generator also takes "subdiv": k (curves) and "transform": T. Omitted
//   parameters keep the defaults of the parameter structs.
//
//   T = {"translate": [x, y, z], "scale": s or [sx, sy, sz],
//        "rotate": {"axis": [x, y, z], "deg": a}}      // every part optional
//   applied as translate * rotate * scale (scale first). Each object's geometries are
//   appended to the one Scene; their instances carry T composed with the instance's own
//   transform (T * own).
//
// Paths: relative paths resolve against the description's directory (base_dir);
// "${MASQ_DATA}" at the start of a path expands to the environment variable MASQ_DATA.
//
// Errors throw masq::Error "<description>: <json path>: <what>", e.g.
//   scene.json: objects[2].transform.scale: expected a number or [x,y,z]
// for JSON syntax errors (with nlohmann's byte position), unknown keys (rejected, so
// typos are caught), wrong types or out-of-range values, unknown generator or prim
// names, an unset MASQ_DATA, and files that fail to load (the loader's own error,
// prefixed with the object's path, e.g. "scene.json: objects[0].file: <loader error>").
#pragma once
#include "scenes/scene.h"
#include <string>

namespace masq {

// Reads a .json scene description from a file; relative paths resolve against its
// directory and errors name `path`.
Scene load_description(const std::string& path);

// The same from text; errors name `name`, relative paths resolve against base_dir
// (empty: the current directory).
Scene load_description_text(const std::string& json, const std::string& name, const std::string& base_dir);

} // namespace masq
