// The two subpaths of bidirectional path tracing and what joining them needs: the random walk that
// extends a subpath bounce by bounce (with the area densities of every vertex in both directions,
// vertex_densities.h), its camera and light starts, the medium a segment crosses, and the
// visibility of a connection. Used by bdpt (every strategy) and lt (the light subpath alone).
//
// Russian roulette: subpaths are terminated with probability 1 - min(1, max(beta) / max(beta_0))
// after a few vertices (beta_0 the throughput the subpath started with: 1 for the camera, the
// emitted power's scale for a light) and survivors divide their throughput by the survival
// probability, so each strategy's estimate stays unbiased. The vertices' densities are those
// *without* the roulette factor, which keeps MIS weights summing to one (every strategy evaluates
// the same function of the path); only their optimality is slightly affected.
#pragma once

#include <vector>

#include "core/sobol_sampler.h"
#include "integrators/bdpt/path_vertex.h"
#include "integrators/integrator.h"
#include "integrators/render_scene.h"

namespace veach {

// What one sample's subpaths are traced against: the scene, the camera at the sample's shutter
// time, that time (every ray's), and the thread's ray count.
struct SubpathContext {
    const RenderScene* rs = nullptr;
    const LightSet* lights = nullptr;
    const CameraModel* camera = nullptr;
    float time = 0.0f;
    ThreadStats* stats = nullptr;
};

// Told of every segment a camera subpath travels when the scene has shaped lights (areas,
// spheres): they are not scene geometry, so a segment may cross one on its way to the next hit.
class SegmentObserver {
public:
    virtual ~SegmentObserver() = default;
    // The segment from `origin` along `dir` up to t_max (k_infinity: it escaped), leaving vertex
    // path[count - 1] with throughput `beta`, solid-angle density pdf_w, through medium `sigma`.
    virtual void segment(std::vector<PathVertex>& path, int count, const Vec3& origin, const Vec3& dir, float t_max,
                         const Rgb& beta, const Rgb& sigma, float pdf_w) = 0;
};

// Fills a surface vertex from a hit and builds its BSDF facing the arriving direction `dir`.
// footprint_width: the camera ray's cone at the hit (texture level of detail), 0 elsewhere.
void fill_surface_vertex(const RenderScene& rs, const RayHit& rh, const Vec3& dir, PathVertex* v,
                         float footprint_width = 0.0f);

// KHR_materials_volume. Media are the interiors of closed, non-nested transmissive meshes, as the
// path tracer assumes; cameras, lights and the environment are in air. A vertex knows the medium
// its own subpath arrived through (sigma_in); a segment leaving it on that side travels in the
// same medium, one leaving through a transmissive surface travels in the mesh's interior when it
// enters and in air when it leaves. Beer-Lambert transmittance is part of each edge's throughput:
// it is symmetric in the two ends and no sampling decision depends on it, so every strategy's
// densities, and with them the MIS weights, are those of the medium-free path. A connection edge
// takes its medium from the camera-side end (the path tracer's light-sample rule); in a closed
// scene the light-side end agrees, since the edge is unoccluded.
// Inline: every connection asks it (an out-of-line call cost bdpt 33 instructions per sample on
// cornell).
inline Rgb medium_toward(const PathVertex& v, const Vec3& w) {
    if (v.kind != PathVertex::Kind::Surface) return v.sigma_in;
    return v.bsdf.medium_toward(w, v.sigma_in, *v.material);
}

// Extends `path`, whose vertex count - 1 was just sampled with solid-angle density pdf_w in
// direction `dir` from `origin`, up to max_vertices vertices; returns the new count.
// roulette_scale: 1 / the throughput the subpath started with. A camera subpath that escapes ends
// on a light at infinity if the scene has one.
int random_walk(const SubpathContext& ctx, std::vector<PathVertex>& path, int count, Vec3 origin, Vec3 dir, Rgb beta,
                float pdf_w, TransportMode mode, int max_vertices, Sampler& rng, float roulette_scale,
                SegmentObserver* observer = nullptr);

// The camera subpath through film position (fx, fy): at most max_depth + 2 vertices.
int trace_camera_subpath(const SubpathContext& ctx, std::vector<PathVertex>& path, float fx, float fy, int max_depth,
                         Sampler& rng, SegmentObserver* observer = nullptr);
// A light subpath from a light chosen by power: at most max_depth + 1 vertices; 0 when the scene
// has no light to start from.
int trace_light_subpath(const SubpathContext& ctx, std::vector<PathVertex>& path, int max_depth, Sampler& rng);

// Whether nothing blocks the segment between vertices a and b (one shadow ray, counted).
bool visible(const SubpathContext& ctx, const PathVertex& a, const PathVertex& b);

}  // namespace veach
