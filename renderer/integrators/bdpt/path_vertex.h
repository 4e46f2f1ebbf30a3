// A vertex of a camera or light subpath, with the two area densities bidirectional MIS needs:
// pdf_fwd, the density with which its own subpath generated it, and pdf_rev, the density with
// which the other subpath would have generated it.
#pragma once

#include <cstdint>

#include "core/rgb.h"
#include "materials/surface_bsdf.h"
#include "scene/surface_attributes.h"

namespace veach {

struct PathVertex {
    enum class Kind : uint8_t { Camera, Light, Surface };

    Kind kind = Kind::Surface;
    bool delta = false;        // scattering here is a Dirac delta (or: a delta camera)
    bool delta_light = false;  // a light vertex with a delta position or direction
    bool infinite = false;     // a directional light's vertex: "at infinity"
    Vec3 p;
    Vec3 p_error;
    Vec3 ng;                  // geometric normal (surfaces, area lights)
    bool has_normal = false;  // false for the camera, point, spot and directional lights
    Rgb beta;                 // path throughput up to and including this vertex's sampling
    // KHR_materials_volume: sigma_a of the medium the subpath's segment arriving here crossed
    // (zero for air; camera and light vertices are in air). See medium_toward().
    Rgb sigma_in;
    float pdf_fwd = 0, pdf_rev = 0;
    // Surfaces:
    SurfaceBsdf bsdf;  // black until a hit fills it (builds nothing)
    const Material* material = nullptr;
    SurfaceAttributes attr;
    uint32_t instance = 0, prim = 0;
    float b1 = 0, b2 = 0;  // barycentrics of the hit, to shade the point again (texture footprints)
    // Lights (light vertices, and surface vertices on an emitter):
    int64_t light = -1;
    Vec3 light_dir;  // directional light vertex: the direction light travels

    // Makes this slot a fresh camera or light vertex. The BSDF is left as it was: endpoints never
    // read it, and building a default one per path cost as much as a connection (perf, cornell).
    void reset_endpoint(Kind k) {
        kind = k;
        delta = delta_light = infinite = has_normal = false;
        p = p_error = ng = light_dir = Vec3();
        beta = sigma_in = Rgb(0.0f);
        pdf_fwd = pdf_rev = 0.0f;
        material = nullptr;
        attr = SurfaceAttributes();
        instance = prim = 0;
        b1 = b2 = 0;
        light = -1;
    }
};

}  // namespace veach
