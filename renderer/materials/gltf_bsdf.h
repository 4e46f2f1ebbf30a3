// The glTF material's BSDF in the local shading frame (normal = +z): the metallic-roughness
// model of the spec's Appendix B, made energy-conserving, plus KHR_materials_transmission.
//
//   f = metallic * metal  +  (1 - metallic) * ((1 - t) * opaque_dielectric  +  t * transmissive)
//
//   metal             = MicrofacetReflection(F0 = base, F90 = 1)          (with multiple scattering)
//   opaque_dielectric = MicrofacetReflection(F0, F90 from ior/specular)  +  layered diffuse
//   transmissive      = the rough dielectric interface of Walter et al. 2007, refraction tinted
//                       by the base colour (dielectric_transmission.h)
//
// and over it, as KHR_materials_sheen and KHR_materials_clearcoat stack them,
//
//   f_total = c * coat  +  min(1 - c E_c(mu_o), 1 - c E_c(mu_i)) * (sheen + s_scale * f)
//
// with coat = MicrofacetReflection(F0 0.04, F90 1, clearcoat roughness) and s_scale the sheen's
// albedo scaling (sheen_charlie.h). The min() form is the sheen extension's; it is reciprocal and
// conserving for any layer beneath (its albedo is at most 1 - c E_c(mu_o) times the layer's).
//
// Layered diffuse. Appendix B's fresnel_mix weights the Lambert base by 1 - F(v.h), which
// gains energy at grazing angles and depends on h, not only on the directions' albedos. We use
// albedo scaling instead (Kulla & Conty 2017, section "Layering"), reciprocal by construction:
//
//   diffuse(wo, wi) = base / pi * (1 - E_spec(mu_o)) (1 - E_spec(mu_i)) / (1 - E_spec_avg)
//
// whose albedo is exactly base * (1 - E_spec(mu_o)): what the specular layer does not reflect
// goes into the base, never more. With F0 = F90 = 0 (no specular layer) it is exactly Lambert.
//
// wo may lie below the frame (z < 0) when a bidirectional integrator evaluates a reverse
// density: the frame is then mirrored and the relative index inverted.
//
// Cost (docs/BENCHMARKS.md, "Where a sample's time goes"). Everything that depends on wo only
// through mu_o = |wo.z| (the albedo-table lookups and the lobe probabilities) is computed once per
// hit by set_outgoing() and reused by every eval / pdf_w / sample call for that wo; other wo
// (reverse densities) are computed afresh, so results never depend on the cache. A material
// with no specular, metal, transmission, coat or sheen (F0 = F90 = 0: Blender's Specular 0) is
// exactly Lambert, and takes a path that skips the microfacet machinery altogether.
#pragma once

#include "materials/gltf_material.h"
#include "materials/microfacet_reflection.h"

namespace veach {

// A direction drawn from a BSDF. For a Dirac-delta lobe (a smooth mirror or smooth refraction)
// pdf_w is the discrete probability of choosing that event and weight already folds f cos / pdf.
struct BsdfSample {
    Vec3 wi;
    Rgb weight;      // f |cos| / pdf (times the adjoint correction in importance mode)
    float pdf_w = 0;
    bool delta = false;
};

// Below this GGX alpha (roughness about 0.01) the specular lobes are treated as perfectly smooth:
// Dirac deltas, sampled exactly and never evaluated by connections or light samples.
inline constexpr float k_delta_alpha = 1e-4f;

class GltfBsdf {
public:
    // eta: index of refraction below the frame (z < 0) relative to above it; a transmissive
    // surface hit from outside has eta = ior, from inside 1 / ior.
    explicit GltfBsdf(const ShadingInputs& in, float eta = 1.5f);

    // f(wo, wi) of the non-delta lobes, without the cosine. Transmission carries the 1/eta^2
    // radiance scaling in Radiance mode only.
    Rgb eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const;
    // Solid-angle density with which sample() produces wi given wo through a non-delta lobe.
    float pdf_w(const Vec3& wo, const Vec3& wi) const;
    // Draws wi; returns false when no direction was produced.
    bool sample(const Vec3& wo, float u_lobe, float u1, float u2, BsdfSample* out,
                TransportMode mode = TransportMode::Radiance) const;

    // Caches the terms that depend on wo only through mu_o = |wo.z| (call once per hit with the
    // direction the path arrived from; optional: without it every call computes them).
    void set_outgoing(float mu_o) {
        if (!m_lambert) m_out = outgoing(mu_o);
    }

    bool is_black() const { return m_black; }
    // Exactly Lambertian: base / pi on each side, cosine-sampled.
    bool is_lambert() const { return m_lambert; }
    // True when every lobe is a delta: connections and light samples are pointless.
    bool is_pure_delta() const {
        return m_delta && m_w_opaque <= 0.0f && (m_coat <= 0.0f || m_coat_delta) && m_sheen_max <= 0.0f;
    }
    bool has_delta() const { return m_delta || (m_coat > 0.0f && m_coat_delta); }
    bool has_transmission() const { return m_w_trans > 0.0f; }

private:
    struct LobeProbabilities {
        float spec = 0, cosine = 0, trans = 0, coat = 0;
    };
    // What depends on wo only through mu_o (wo mirrored above the frame).
    struct Outgoing {
        float mu = -1.0f;          // never equal to a real |wo.z|: nothing cached yet
        GgxAlbedo e;               // ggx_albedo(mu, alpha)
        GgxAlbedo e_coat;          // ggx_albedo(mu, coat alpha), rough coats only
        Rgb diffuse_factor{1.0f};  // 1 - E_spec(mu)
        float coat = 0, sheen = 0; // coat_albedo(mu), sheen_albedo_max(mu)
        LobeProbabilities p;
    };
    Outgoing outgoing(float mu_o) const;
    // The cached terms when mu_o is the cached direction's, else computed into *scratch.
    const Outgoing& outgoing_at(float mu_o, Outgoing* scratch) const {
        if (mu_o == m_out.mu) return m_out;
        *scratch = outgoing(mu_o);
        return *scratch;
    }
    // How often to sample each lobe: its albedo from wo (from the tables, no integration).
    LobeProbabilities probabilities(float mu_o, const Outgoing& o) const;
    Rgb eval_upper(const Vec3& wo, const Vec3& wi, float eta, TransportMode mode, const Outgoing& o) const;
    Rgb eval_base(const Vec3& wo, const Vec3& wi, float eta, TransportMode mode,
                  const Outgoing& o) const;  // beneath the layers
    float pdf_upper(const Vec3& wo, const Vec3& wi, float eta, const Outgoing& o) const;
    Rgb diffuse_albedo_factor(const GgxAlbedo& e) const;  // 1 - E_spec(mu), per channel
    float coat_albedo(float mu) const;                     // c E_c(mu)
    float sheen_albedo_max(float mu) const;                // max(sheenColor) E_sheen(mu)
    // The scaling of everything beneath the coat and the sheen for the pair (mu_o, mu_i).
    float base_scale(const Outgoing& o, float mu_i) const;
    // The smooth mirror direction, produced by every delta reflection lobe together.
    void mirror_sample(const Vec3& wo, float eta, const Outgoing& o, BsdfSample* out) const;

    Rgb m_base;
    float m_alpha, m_eta;
    float m_w_metal, m_w_opaque, m_w_trans;  // metallic, (1 - metallic)(1 - t), (1 - metallic) t
    MicrofacetReflection m_metal, m_specular;
    Rgb m_diffuse_norm;  // base / (pi (1 - E_spec_avg))
    bool m_black = false, m_delta = false, m_lambert = false;
    float m_coat = 0, m_coat_alpha = 1;  // clearcoat factor and GGX alpha
    bool m_coat_delta = false;
    MicrofacetReflection m_coat_lobe;
    Rgb m_sheen_color;
    float m_sheen_max = 0, m_sheen_roughness = 0, m_sheen_alpha = 1;
    Outgoing m_out;  // set_outgoing()'s cache
};

}  // namespace veach
