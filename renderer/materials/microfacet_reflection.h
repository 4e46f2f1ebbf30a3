// The GGX reflection lobe of glTF's Appendix B with Schlick's Fresnel between F0 and F90, plus
// the multiple-scattering lobe that restores the energy single scattering loses (ggx_energy.h).
// Local frame, wo.z > 0 and wi.z > 0; both parts are symmetric in (wo, wi).
//
//   f(wo, wi) = F(wo.h) D G2 / (4 mu_o mu_i)  +  F_ms f_ms(mu_o, mu_i)
//
// Its directional albedo, needed by the layer beneath it, follows from the tables without
// integration: E_spec(mu) = F0 E(mu) + (F90 - F0) E_w(mu) + F_ms (1 - E(mu)).
#pragma once

#include "core/rgb.h"
#include "materials/fresnel.h"
#include "materials/ggx_energy.h"
#include "materials/microfacet_ggx.h"

namespace veach {

class MicrofacetReflection {
public:
    MicrofacetReflection() = default;
    MicrofacetReflection(const Rgb& f0, const Rgb& f90, float alpha, bool delta)
        : m_f0(f0), m_f90(f90), m_alpha(alpha), m_delta(delta) {
        GgxAlbedo avg = ggx_average_albedo(alpha);
        m_e_avg = avg.e;
        m_f_ms = delta ? Rgb(0.0f) : ggx_multiple_scattering_fresnel(f0, f90, avg.e);
        m_albedo_avg = f0 * avg.e + (f90 - f0) * avg.e_w + m_f_ms * (1.0f - avg.e);
    }

    Rgb fresnel(float cos_h) const { return m_f0 + (m_f90 - m_f0) * schlick_weight(cos_h); }

    // The glossy part (zero for a delta mirror, whose reflection is sampled, never evaluated).
    Rgb eval(const Vec3& wo, const Vec3& wi, const GgxAlbedo& e_o, const GgxAlbedo& e_i) const {
        if (m_delta) return Rgb(0.0f);
        Vec3 h = normalize(wo + wi);
        float single = ggx_d(h, m_alpha) * ggx_g2(wo, wi, m_alpha) / (4.0f * wo.z * wi.z);
        return fresnel(dot(wo, h)) * single + m_f_ms * ggx_multiple_scattering(e_o.e, e_i.e, m_e_avg);
    }

    // Directional albedo E_spec(mu) of the whole lobe, and its single-scattering share.
    Rgb albedo(const GgxAlbedo& e) const { return m_f0 * e.e + (m_f90 - m_f0) * e.e_w + m_f_ms * (1.0f - e.e); }
    Rgb single_scattering_albedo(const GgxAlbedo& e) const { return m_f0 * e.e + (m_f90 - m_f0) * e.e_w; }
    Rgb multiple_scattering_albedo(const GgxAlbedo& e) const { return m_f_ms * (1.0f - e.e); }
    const Rgb& average_albedo() const { return m_albedo_avg; }

private:
    Rgb m_f0, m_f90, m_f_ms, m_albedo_avg;
    float m_alpha = 1, m_e_avg = 1;
    bool m_delta = false;
};

}  // namespace veach
