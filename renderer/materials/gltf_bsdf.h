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
//
// The clearcoat's own normal (KHR_materials_clearcoat's clearcoatNormalTexture, or the
// interpolated vertex normal when the base is normal-mapped and the coat is not: the extension
// says the base's normal map does not apply to the coat) is a unit vector cn in this frame,
// set_coat_normal(). The coat lobe is then the same GGX reflection evaluated in cn's frame, its
// albedo and the layering's min() use cosines to cn, and the integrand, which the caller
// multiplies by |wi.z| (the base's shading normal), is kept within the coat's own:
//
//   coat'(wo, wi) = coat_cn(wo, wi) min(1, (wo.cn) / wo.z) min(1, (wi.cn) / wi.z)
//
// Symmetric in wo and wi (reciprocal), and its albedo, the integral of coat' wi.z, is at most the
// integral of coat_cn (wi.cn), the coat's albedo E_c(wo.cn): the layer conserves energy as an
// untilted one does. It loses the little light the coat would send where wi.cn > wi.z; a tilted
// coat's delta mirror (smooth coats) is its own event, reflected about cn.
#pragma once

#include "materials/gltf_material.h"
#include "materials/microfacet_reflection.h"
#include "materials/transport_mode.h"

namespace veach {

// A direction drawn from a BSDF. For a Dirac-delta lobe (a smooth mirror or smooth refraction)
// pdf_w is the discrete probability of choosing that event and weight already folds f cos / pdf.
struct BsdfSample {
    Vec3 wi;
    Rgb weight;  // f |cos| / pdf (times the adjoint correction in importance mode)
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

    // Caches the terms that depend on wo (only through mu_o = |wo.z| unless the coat is tilted):
    // call once per hit with the direction the path arrived from; optional, without it every
    // call computes them.
    void set_outgoing(const Vec3& wo) {
        if (!m_lambert && wo.z != 0.0f) m_out = outgoing(upper(wo), wo.z < 0.0f);
    }
    // The coat's shading normal in this frame (unit, z > 0); ignored without a coat. Call before
    // set_outgoing().
    void set_coat_normal(const Vec3& cn);

    bool is_black() const { return m_black; }
    // Exactly Lambertian: base / pi on each side, cosine-sampled.
    bool is_lambert() const { return m_lambert; }
    // True when every lobe is a delta: connections and light samples are pointless.
    bool is_pure_delta() const {
        return m_delta && m_w_opaque <= 0.0f && (m_coat <= 0.0f || m_coat_delta) && m_sheen_max <= 0.0f;
    }
    bool has_delta() const { return m_delta || (m_coat > 0.0f && m_coat_delta); }
    bool has_transmission() const { return m_w_trans > 0.0f; }
    // The relative index seen from below the shading frame: the interior's inverse, or for a thin
    // wall (air on both sides) the same index.
    float below_eta() const { return m_thin ? m_eta : 1.0f / m_eta; }

private:
    struct LobeProbabilities {
        float spec = 0, cosine = 0, trans = 0, coat = 0;
    };
    // What depends on wo only through mu_o (wo mirrored above the frame), or through wo and the
    // side with a tilted coat.
    struct Outgoing {
        Vec3 w{0.0f, 0.0f, -1.0f};  // wo mirrored above the frame; z < 0: nothing cached yet
        bool flipped = false;       // wo was below the frame
        float mu = -1.0f;           // w.z
        float mu_c = -1.0f;         // w.cn: the coat's cosine
        Frame coat_frame;           // the coat's frame in the (mirrored) frame: n = cn
        GgxAlbedo e;                // ggx_albedo(mu, alpha)
        GgxAlbedo e_coat;           // ggx_albedo(mu, coat alpha), rough coats only
        Rgb diffuse_factor{1.0f};   // 1 - E_spec(mu)
        float coat = 0, sheen = 0;  // coat_albedo(mu), sheen_albedo_max(mu)
        LobeProbabilities p;
    };
    static Vec3 upper(const Vec3& w) { return {w.x, w.y, std::fabs(w.z)}; }
    Outgoing outgoing(const Vec3& wo_up, bool flipped) const;
    // The cached terms when wo is the cached direction, else computed into *scratch.
    const Outgoing& outgoing_at(const Vec3& wo_up, bool flipped, Outgoing* scratch) const {
        bool same = wo_up.z == m_out.mu &&
                    (!m_coat_tilted || (wo_up.x == m_out.w.x && wo_up.y == m_out.w.y && flipped == m_out.flipped));
        if (same) return m_out;
        *scratch = outgoing(wo_up, flipped);
        return *scratch;
    }
    // The cosine of w to the coat's normal and its factor min(1, w.cn / w.z) (1 untilted).
    float coat_cos(const Vec3& w, const Outgoing& o) const { return m_coat_tilted ? dot(w, o.coat_frame.n) : w.z; }
    float coat_tilt_factor(const Vec3& w, float mu_c) const {
        return m_coat_tilted ? (w.z != 0.0f ? std::min(1.0f, std::max(0.0f, mu_c) / std::fabs(w.z)) : 0.0f) : 1.0f;
    }
    // A tilted smooth coat's mirror about cn.
    bool coat_mirror_sample(const Vec3& wo, const Outgoing& o, BsdfSample* out) const;
    // How often to sample each lobe: its albedo from wo (from the tables, no integration).
    LobeProbabilities probabilities(float mu_o, const Outgoing& o) const;
    Rgb eval_upper(const Vec3& wo, const Vec3& wi, float eta, TransportMode mode, const Outgoing& o) const;
    Rgb eval_base(const Vec3& wo, const Vec3& wi, float eta, TransportMode mode,
                  const Outgoing& o) const;  // beneath the layers
    float pdf_upper(const Vec3& wo, const Vec3& wi, float eta, const Outgoing& o) const;
    Rgb diffuse_albedo_factor(const GgxAlbedo& e) const;  // 1 - E_spec(mu), per channel
    float coat_albedo(float mu) const;                    // c E_c(mu)
    float sheen_albedo_max(float mu) const;               // max(sheenColor) E_sheen(mu)
    // The scaling of everything beneath the coat and the sheen for the pair (mu_o, mu_i).
    float base_scale(const Outgoing& o, float mu_i, float mu_i_coat) const;
    // The smooth mirror direction, produced by every delta reflection lobe together.
    void mirror_sample(const Vec3& wo, float eta, const Outgoing& o, BsdfSample* out) const;

    Rgb m_base;
    float m_alpha, m_eta;
    float m_w_metal, m_w_opaque, m_w_trans;  // metallic, (1 - metallic)(1 - t), (1 - metallic) t
    MicrofacetReflection m_metal, m_specular;
    Rgb m_diffuse_norm;  // base / (pi (1 - E_spec_avg))
    bool m_black = false, m_delta = false, m_lambert = false;
    bool m_thin = false;  // ShadingInputs::thin_walled: the same index from both sides
    float m_coat = 0, m_coat_alpha = 1;  // clearcoat factor and GGX alpha
    bool m_coat_delta = false;
    bool m_coat_tilted = false;  // the coat has its own normal (set_coat_normal)
    Vec3 m_coat_normal{0.0f, 0.0f, 1.0f};
    MicrofacetReflection m_coat_lobe;
    Rgb m_sheen_color;
    float m_sheen_max = 0, m_sheen_roughness = 0, m_sheen_alpha = 1;
    Outgoing m_out;  // set_outgoing()'s cache
};

}  // namespace veach
