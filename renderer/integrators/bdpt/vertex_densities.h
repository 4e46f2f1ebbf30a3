// The density conversions of bidirectional path tracing: a direction's solid-angle density turned
// into the area density of the vertex it reaches, and the densities with which a light produces a
// vertex as a path's origin or its first bounce (pbrt-v3 section 16.3, Veach 1997 section 10.2).
// Each vertex stores its densities in the area measure so that the MIS weight can compare
// strategies that sample the same vertex from opposite ends.
#pragma once

#include <cmath>

#include "integrators/bdpt/path_vertex.h"
#include "lights/light_set.h"

namespace veach {

// A zero density (a delta bounce's, or a vertex no strategy samples from that side) stands for 1 in
// the MIS ratio recurrence; the delta flags exclude the strategies that would need it.
inline float remap0(float v) { return v != 0.0f ? v : 1.0f; }

// Converts a solid-angle density at `from` toward `to` into an area density at `to`: divided by
// the squared distance, times the cosine at `to` when it has a surface. At infinity directions are
// the area measure, and the density is returned as it is.
inline float to_area_density(float pdf_w, const PathVertex& from, const PathVertex& to) {
    if (to.infinite) return pdf_w;
    Vec3 d = to.p - from.p;
    float dist2 = length_squared(d);
    if (!(dist2 > 0.0f)) return 0.0f;
    float pdf = pdf_w / dist2;
    if (to.has_normal) pdf *= std::fabs(dot(to.ng, d)) / std::sqrt(dist2);
    return pdf;
}

// Area density with which the light sampler produces point v (on light v.light) as a light
// subpath's origin, selection included; at infinity the density of its direction.
float light_origin_pdf_a(const LightSet& lights, const PathVertex& v, const Vec3& dir_out);

// Area density at `to` of a particle emitted from light vertex (or emitter surface) `light_v`.
float light_emission_pdf_area(const LightSet& lights, const PathVertex& light_v, const PathVertex& to);

}  // namespace veach
