// The glTF 2.0 metallic-roughness BRDF (spec Appendix B) with KHR_materials_ior and
// KHR_materials_specular:
//
//   f = metallic * F_metal * S  +  (1 - metallic) * ((1 - max(F_diel)) * base / pi  +  F_diel * S)
//
// with S the GGX specular lobe D * G2 / (4 |n.wo| |n.wi|) (height-correlated Smith), F_metal the
// Schlick Fresnel with F0 = base colour, and F_diel the Schlick Fresnel between
// F0 = min(((ior-1)/(ior+1))^2 * specularColor, 1) * specular and F90 = specular.
// All Fresnel terms use |wo.h| = |wi.h|, so f is symmetric in (wo, wi): reciprocal.
#pragma once

#include <cstdint>

#include "core/rgb.h"
#include "scene/scene.h"

namespace veach {

enum class TransportMode : uint8_t { Radiance, Importance };

// A material's parameters at one surface point, after textures.
struct ShadingInputs {
    Rgb base_color{1, 1, 1};
    float opacity = 1;
    float metallic = 0;
    float alpha = 1;           // GGX alpha = roughness^2
    Rgb dielectric_f0{0.04f, 0.04f, 0.04f};
    float dielectric_f90 = 1;
    Rgb emission;
};

struct SurfaceAttributes {
    Vec2 uv[2];
    Rgba color{1, 1, 1, 1};
};

// Looks up the material's textures and combines them with its factors.
ShadingInputs evaluate_material(const Material& m, const Scene& scene, const SurfaceAttributes& attr);
// Only the emitted radiance (cheaper, for light sampling).
Rgb evaluate_emission(const Material& m, const Scene& scene, const SurfaceAttributes& attr);

// A direction drawn from a BSDF. For a Dirac-delta lobe (a smooth mirror) pdf_w is the
// discrete probability of choosing that lobe and weight already folds f cos / pdf.
struct BsdfSample {
    Vec3 wi;
    Rgb weight;      // f |cos| / pdf (times the adjoint correction in importance mode)
    float pdf_w = 0;
    bool delta = false;
};

// Below this GGX alpha (roughness about 0.01) the specular lobe is treated as a perfect mirror:
// a Dirac delta, sampled exactly and never evaluated by connections or light samples.
inline constexpr float k_delta_alpha = 1e-4f;

// The BRDF in the local shading frame (normal = +z). wo and wi point away from the surface.
class GltfBsdf {
public:
    explicit GltfBsdf(const ShadingInputs& in);

    // f(wo, wi) of the non-delta lobes, without the cosine.
    Rgb eval(const Vec3& wo, const Vec3& wi) const;
    // Solid-angle density with which sample() produces wi given wo through a non-delta lobe.
    float pdf_w(const Vec3& wo, const Vec3& wi) const;
    // Draws wi; returns false when no direction was produced.
    bool sample(const Vec3& wo, float u_lobe, float u1, float u2, BsdfSample* out) const;

    bool is_black() const { return m_black; }
    // True when every lobe is a delta: connections and light samples are pointless.
    bool is_pure_delta() const { return m_delta_specular && m_metallic >= 1.0f; }
    bool has_delta() const { return m_delta_specular; }

private:
    float specular_probability(const Vec3& wo) const;

    Rgb m_base;
    float m_metallic, m_alpha;
    Rgb m_f0, m_diffuse_weight;
    float m_f90;
    bool m_black;
    bool m_delta_specular;
};

}  // namespace veach
