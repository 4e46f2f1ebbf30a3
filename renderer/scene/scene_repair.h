// Degenerate geometry, repaired or dropped once after import (by the scene load,
// load/scene_load.h), before anything is built from the scene. Files from every exporter carry
// faces the renderer cannot use as they are: zero-area and collinear triangles (no normal, no
// area to sample), repeated corners, NaN or infinite attributes (one NaN spreads to every pixel
// that sees it), zero-length or non-unit normals, and the same face stored twice. Each case is
// counted in Scene::repaired and summarised in one warning; nothing here depends on the scene's
// size.
#pragma once

#include "scene/scene.h"

namespace veach {

// Repairs `scene` in place and returns what it changed (also added to scene.repaired). When
// anything changed, appends one warning to scene.warnings naming the counts.
//  - triangles with an index past the vertex array, a non-finite corner, zero area, collinear
//    corners (|e1 x e2| <= 1e-6 |e1| |e2|: the normal would be rounding noise) or repeated
//    corners are dropped;
//  - a triangle with the same three corner positions as an earlier one of the same mesh
//    (whatever the order or winding) is dropped: coincident faces only flicker between materials;
//  - NaN, infinite or zero-length normals become the area-weighted average of the normals of the
//    faces around the vertex; other normals are normalised;
//  - NaN or infinite texture coordinates become 0, vertex colours 1;
//  - punctual lights with a NaN or infinite position, direction, intensity or cone are dropped.
// Partially overlapping coplanar faces are left alone: the hit point's error bound already
// keeps rays leaving one of them from stopping on the other.
RepairCounts repair_scene(Scene& scene);

// Moves the whole scene (instances, cameras, punctual lights) so that its bounding box is centred
// on the origin, when it lies farther from the origin than its own size. Float coordinates near
// 1e5 carry an ulp of 0.008, and every hit point's error bound (and so every ray offset) grows
// with its coordinates' magnitude: near the origin the same scene keeps all its precision. The
// subtraction is done in double on the transforms' translations, so no shape changes, and the
// image does not either: nothing the renderer computes depends on where the origin is. Returns
// the offset subtracted (zero when the scene was left alone). Not part of repair_scene: importers
// keep the file's coordinates; the scene load calls it last, after the pose.
Vec3 rebase_scene(Scene& scene);
// The same with the scene's bounds (Scene::bounds()) already known, e.g. kept per instance
// across a sequence's frames.
Vec3 rebase_scene(Scene& scene, const Bounds3& bounds);

// A scene with no light at all (no punctual light, no emissive surface, no environment) renders
// black. glTF viewers light such a scene with a uniform white world; so does Veach: this enables
// a uniform environment of radiance 1, warns once, and returns true. The scene load calls it after
// applying the environment options, so an explicit --env always wins.
bool light_unlit_scene(Scene& scene);

}  // namespace veach
