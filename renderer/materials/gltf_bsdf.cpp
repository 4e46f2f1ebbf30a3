#include "materials/gltf_bsdf.h"

#include "materials/dielectric_transmission.h"
#include "materials/lambert_diffuse.h"
#include "materials/sheen_charlie.h"

namespace veach {
namespace {

Vec3 mirror_z(const Vec3& v) { return {v.x, v.y, -v.z}; }

DielectricLobeValue dielectric_lobe(bool thin, const Vec3& wo, const Vec3& wi, float alpha, float eta, bool radiance) {
    return thin ? thin_dielectric_eval(wo, wi, alpha, eta) : dielectric_eval(wo, wi, alpha, eta, radiance);
}

// Never let a lobe with weight starve entirely: keeps the variance bounded.
constexpr float k_min_lobe_probability = 0.05f;

}  // namespace

GltfBsdf::GltfBsdf(const ShadingInputs& in, float eta)
    : m_base(in.base_color), m_alpha(in.alpha), m_eta(eta > 0.0f ? eta : 1.0f), m_thin(in.thin_walled) {
    float metallic = clamp(in.metallic, 0.0f, 1.0f);
    float t = clamp(in.transmission, 0.0f, 1.0f);
    m_w_metal = metallic;
    m_w_opaque = (1.0f - metallic) * (1.0f - t);
    m_w_trans = (1.0f - metallic) * t;
    m_delta = m_alpha < k_delta_alpha;
    m_coat = clamp(in.clearcoat, 0.0f, 1.0f);
    m_sheen_color =
        Rgb(std::max(0.0f, in.sheen_color.r), std::max(0.0f, in.sheen_color.g), std::max(0.0f, in.sheen_color.b));
    m_sheen_max = std::min(1.0f, m_sheen_color.max());
    // No metal, no transmission, a specular layer with F0 = F90 = 0 (which reflects nothing at
    // any angle, nor loses anything to multiple scattering: E_spec = 0), no coat, no sheen: the
    // layered diffuse below is then exactly base / pi, and nothing else needs building.
    m_lambert = m_w_metal <= 0.0f && m_w_trans <= 0.0f && in.dielectric_f0.is_black() && in.dielectric_f90 <= 0.0f &&
                m_coat <= 0.0f && m_sheen_max <= 0.0f;
    m_black = m_lambert && m_base.is_black();
    if (m_lambert) {
        m_diffuse_norm = m_base * k_inv_pi;
        return;
    }
    m_metal = MicrofacetReflection(m_base, Rgb(1.0f), m_alpha, m_delta);
    m_specular = MicrofacetReflection(in.dielectric_f0, Rgb(in.dielectric_f90), m_alpha, m_delta);
    Rgb avg = m_specular.average_albedo();
    auto norm = [](float base, float e_avg) { return e_avg < 1.0f ? base * k_inv_pi / (1.0f - e_avg) : 0.0f; };
    m_diffuse_norm = Rgb(norm(m_base.r, avg.r), norm(m_base.g, avg.g), norm(m_base.b, avg.b));
    if (m_coat > 0.0f) {
        m_coat_alpha = std::max(in.clearcoat_alpha, k_min_ggx_alpha);
        m_coat_delta = m_coat_alpha < k_delta_alpha;
        // Clearcoat: ior 1.5, F0 = ((1.5 - 1) / (1.5 + 1))^2 = 0.04 (the extension's fixed value).
        m_coat_lobe = MicrofacetReflection(Rgb(0.04f), Rgb(1.0f), m_coat_alpha, m_coat_delta);
    }
    if (m_sheen_max > 0.0f) {
        m_sheen_roughness = in.sheen_roughness;
        m_sheen_alpha = sheen_alpha(in.sheen_roughness);
    }
}

void GltfBsdf::set_coat_normal(const Vec3& cn) {
    if (m_coat <= 0.0f || m_lambert) return;
    float l = length(cn);
    if (!(l > 0.0f) || !std::isfinite(l)) return;
    Vec3 n = cn / l;
    // Below the base frame the coat would face into the surface; within float noise of +z it is
    // the untilted coat, which keeps the mu-only cache and the shared mirror event.
    if (!(n.z > 0.0f) || n.z >= 1.0f - 1e-6f) return;
    m_coat_tilted = true;
    m_coat_normal = n;
}

float GltfBsdf::coat_albedo(float mu) const {
    if (m_coat <= 0.0f || !(mu > 0.0f)) return 0.0f;
    if (m_coat_delta) return m_coat * m_coat_lobe.fresnel(mu).r;
    return m_coat * m_coat_lobe.albedo(ggx_albedo(mu, m_coat_alpha)).r;
}

float GltfBsdf::sheen_albedo_max(float mu) const {
    return m_sheen_max > 0.0f ? m_sheen_max * sheen_albedo(mu, m_sheen_roughness) : 0.0f;
}

float GltfBsdf::base_scale(const Outgoing& o, float mu_i, float mu_i_coat) const {
    if (m_coat <= 0.0f && m_sheen_max <= 0.0f) return 1.0f;
    float coat = std::min(1.0f - o.coat, 1.0f - coat_albedo(mu_i_coat));
    float sheen = std::min(1.0f - o.sheen, 1.0f - sheen_albedo_max(mu_i));
    return std::max(0.0f, coat) * std::max(0.0f, sheen);
}

GltfBsdf::Outgoing GltfBsdf::outgoing(const Vec3& wo_up, bool flipped) const {
    Outgoing o;
    float mu_o = wo_up.z;
    o.w = wo_up;
    o.flipped = flipped;
    o.mu = mu_o;
    o.mu_c = mu_o;
    if (m_coat_tilted) {
        // Below the frame the coat is the mirror image of the one above: -cn, mirrored.
        Vec3 cn = flipped ? Vec3(-m_coat_normal.x, -m_coat_normal.y, m_coat_normal.z) : m_coat_normal;
        o.coat_frame = Frame(cn);
        o.mu_c = dot(wo_up, cn);
    }
    o.e = ggx_albedo(mu_o, m_alpha);
    bool coat_on = m_coat > 0.0f && o.mu_c > 0.0f;
    if (coat_on && !m_coat_delta) o.e_coat = ggx_albedo(o.mu_c, m_coat_alpha);
    o.diffuse_factor = diffuse_albedo_factor(o.e);
    // The coat's albedo from the lookup just made (coat_albedo() would repeat it).
    o.coat = !coat_on       ? 0.0f
             : m_coat_delta ? m_coat * m_coat_lobe.fresnel(o.mu_c).r
                            : m_coat * m_coat_lobe.albedo(o.e_coat).r;
    o.sheen = sheen_albedo_max(mu_o);
    o.p = probabilities(mu_o, o);
    return o;
}

Rgb GltfBsdf::diffuse_albedo_factor(const GgxAlbedo& e) const {
    Rgb a = m_specular.albedo(e);
    return Rgb(std::max(0.0f, 1.0f - a.r), std::max(0.0f, 1.0f - a.g), std::max(0.0f, 1.0f - a.b));
}

GltfBsdf::LobeProbabilities GltfBsdf::probabilities(float mu_o, const Outgoing& o) const {
    LobeProbabilities p;
    const GgxAlbedo& e_o = o.e;
    Rgb metal_single = m_delta ? m_metal.fresnel(mu_o) : m_metal.single_scattering_albedo(e_o);
    Rgb spec_single = m_delta ? m_specular.fresnel(mu_o) : m_specular.single_scattering_albedo(e_o);
    p.spec = m_w_metal * metal_single.average() + m_w_opaque * spec_single.average();
    p.cosine =
        m_w_metal * m_metal.multiple_scattering_albedo(e_o).average() +
        m_w_opaque * (m_specular.multiple_scattering_albedo(e_o).average() + (m_base * o.diffuse_factor).average());
    p.trans = m_w_trans;
    // The layers on top: everything beneath is dimmed by them, the sheen is sampled by the
    // cosine lobe, the coat by its own visible normals.
    float coat_o = o.coat, sheen_o = o.sheen;
    float beneath = (1.0f - coat_o) * (1.0f - sheen_o);
    p.spec *= beneath;
    p.cosine = p.cosine * beneath + (1.0f - coat_o) * sheen_o;
    p.trans *= beneath;
    p.coat = coat_o;
    float total = p.spec + p.cosine + p.trans + p.coat;
    if (!(total > 0.0f)) return {0.0f, 1.0f, 0.0f, 0.0f};
    p.spec /= total;
    p.cosine /= total;
    p.trans /= total;
    p.coat /= total;
    // Floors only for lobes that can carry light at all, then renormalise.
    bool spec_on = m_w_metal > 0.0f || (m_w_opaque > 0.0f && spec_single.max() > 0.0f);
    bool cos_on = m_w_opaque > 0.0f || (m_w_metal > 0.0f && !m_delta) || m_sheen_max > 0.0f;
    if (spec_on) p.spec = std::max(p.spec, k_min_lobe_probability);
    if (cos_on) p.cosine = std::max(p.cosine, k_min_lobe_probability);
    if (m_w_trans > 0.0f) p.trans = std::max(p.trans, k_min_lobe_probability);
    if (!spec_on) p.spec = 0.0f;
    if (!cos_on) p.cosine = 0.0f;
    if (m_coat > 0.0f && o.mu_c > 0.0f) p.coat = std::max(p.coat, k_min_lobe_probability);
    total = p.spec + p.cosine + p.trans + p.coat;
    p.spec /= total;
    p.cosine /= total;
    p.trans /= total;
    p.coat /= total;
    return p;
}

// wo.z > 0 here; eta is the relative index below.
Rgb GltfBsdf::eval_upper(const Vec3& wo, const Vec3& wi, float eta, TransportMode mode, const Outgoing& o) const {
    Rgb f = eval_base(wo, wi, eta, mode, o);
    if (m_coat <= 0.0f && m_sheen_max <= 0.0f) return f;
    float mu_i_coat = coat_cos(wi, o);
    // The coat's cosine on wi's own side (0 when wi is beyond the coat's horizon there), so that
    // base_scale treats wi exactly as it treats wo in the reverse query (reciprocity).
    f *= base_scale(o, std::fabs(wi.z), std::max(0.0f, wi.z > 0.0f ? mu_i_coat : -mu_i_coat));
    if (wi.z > 0.0f) {
        float coat_scale = std::min(1.0f - o.coat, 1.0f - coat_albedo(mu_i_coat));
        if (m_sheen_max > 0.0f) f += m_sheen_color * (sheen_eval(wo, wi, m_sheen_alpha) * coat_scale);
        if (m_coat > 0.0f && !m_coat_delta && o.mu_c > 0.0f && mu_i_coat > 0.0f) {
            if (!m_coat_tilted) {
                f += m_coat_lobe.eval(wo, wi, o.e_coat, ggx_albedo(wi.z, m_coat_alpha)) * m_coat;
            } else {
                Vec3 wo_c = o.coat_frame.to_local(wo), wi_c = o.coat_frame.to_local(wi);
                float tilt = coat_tilt_factor(wo, o.mu_c) * coat_tilt_factor(wi, mu_i_coat);
                f += m_coat_lobe.eval(wo_c, wi_c, o.e_coat, ggx_albedo(wi_c.z, m_coat_alpha)) * (m_coat * tilt);
            }
        }
    }
    return f;
}

Rgb GltfBsdf::eval_base(const Vec3& wo, const Vec3& wi, float eta, TransportMode mode, const Outgoing& o) const {
    if (wi.z > 0.0f) {
        const GgxAlbedo& e_o = o.e;
        GgxAlbedo e_i = ggx_albedo(wi.z, m_alpha);
        Rgb f(0.0f);
        if (m_w_metal > 0.0f) f += m_metal.eval(wo, wi, e_o, e_i) * m_w_metal;
        if (m_w_opaque > 0.0f) {
            Rgb diffuse = m_diffuse_norm * o.diffuse_factor * diffuse_albedo_factor(e_i);
            f += (m_specular.eval(wo, wi, e_o, e_i) + diffuse) * m_w_opaque;
        }
        if (m_w_trans > 0.0f && !m_delta)
            f += Rgb(dielectric_lobe(m_thin, wo, wi, m_alpha, eta, mode == TransportMode::Radiance).f * m_w_trans);
        return f;
    }
    if (wi.z < 0.0f && m_w_trans > 0.0f && !m_delta)
        return m_base * (dielectric_lobe(m_thin, wo, wi, m_alpha, eta, mode == TransportMode::Radiance).f * m_w_trans);
    return Rgb(0.0f);
}

float GltfBsdf::pdf_upper(const Vec3& wo, const Vec3& wi, float eta, const Outgoing& o) const {
    const LobeProbabilities& p = o.p;
    float pdf = 0.0f;
    if (wi.z > 0.0f) {
        if (p.spec > 0.0f && !m_delta) pdf += p.spec * ggx_reflection_pdf_w(wo, normalize(wo + wi), m_alpha);
        if (p.cosine > 0.0f) pdf += p.cosine * lambert_pdf_w(wo, wi);
    }
    if (p.trans > 0.0f && !m_delta) pdf += p.trans * dielectric_lobe(m_thin, wo, wi, m_alpha, eta, true).pdf_w;
    if (p.coat > 0.0f && !m_coat_delta && wi.z > 0.0f) {
        if (!m_coat_tilted) {
            pdf += p.coat * ggx_reflection_pdf_w(wo, normalize(wo + wi), m_coat_alpha);
        } else {
            Vec3 wo_c = o.coat_frame.to_local(wo), wi_c = o.coat_frame.to_local(wi);
            if (wi_c.z > 0.0f) pdf += p.coat * ggx_reflection_pdf_w(wo_c, normalize(wo_c + wi_c), m_coat_alpha);
        }
    }
    return pdf;
}

// Every smooth reflection lobe sends wo to the same mirror direction, so the sample's weight is
// the sum of their Fresnel masses over the sum of their probabilities of choosing it.
void GltfBsdf::mirror_sample(const Vec3& wo, float eta, const Outgoing& o, BsdfSample* out) const {
    const LobeProbabilities& p = o.p;
    Rgb mass(0.0f);
    float prob = 0.0f;
    if (m_coat > 0.0f && m_coat_delta && !m_coat_tilted) {
        mass += m_coat_lobe.fresnel(wo.z) * m_coat;
        prob += p.coat;
    }
    if (m_delta) {
        float fr = m_w_trans > 0.0f ? fresnel_dielectric(wo.z, eta) : 0.0f;
        Rgb base = m_metal.fresnel(wo.z) * m_w_metal + m_specular.fresnel(wo.z) * m_w_opaque + Rgb(fr * m_w_trans);
        Vec3 wi(-wo.x, -wo.y, wo.z);
        mass += base * base_scale(o, wo.z, std::max(0.0f, coat_cos(wi, o)));
        prob += p.spec + p.trans * fr;
    }
    out->wi = Vec3(-wo.x, -wo.y, wo.z);
    out->weight = prob > 0.0f ? mass / prob : Rgb(0.0f);
    out->pdf_w = prob;
    out->delta = true;
}

// The weight of the mirror event is the coat's Fresnel mass times the tilt factors of the class
// comment; for a delta, wi.cn = wo.cn = mu_c, and coat' |wi.z| / (wi.cn) leaves
// min(1, mu_c / wo.z) min(1, wi.z / mu_c) <= 1.
bool GltfBsdf::coat_mirror_sample(const Vec3& wo, const Outgoing& o, BsdfSample* out) const {
    const LobeProbabilities& p = o.p;
    if (!(o.mu_c > 0.0f) || !(p.coat > 0.0f)) return false;
    Vec3 wi = reflect(wo, o.coat_frame.n);
    if (!(wi.z > 0.0f)) return false;
    float tilt = std::min(1.0f, o.mu_c / wo.z) * std::min(1.0f, wi.z / o.mu_c);
    out->wi = wi;
    out->weight = m_coat_lobe.fresnel(o.mu_c) * (m_coat * tilt / p.coat);
    out->pdf_w = p.coat;
    out->delta = true;
    return true;
}

namespace {
bool same_side(const Vec3& wo, const Vec3& wi) { return (wo.z > 0.0f && wi.z > 0.0f) || (wo.z < 0.0f && wi.z < 0.0f); }
}  // namespace

Rgb GltfBsdf::eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    if (m_lambert) return same_side(wo, wi) ? m_diffuse_norm : Rgb(0.0f);
    Outgoing scratch;
    if (wo.z > 0.0f) return eval_upper(wo, wi, m_eta, mode, outgoing_at(wo, false, &scratch));
    if (wo.z < 0.0f)
        return eval_upper(mirror_z(wo), mirror_z(wi), below_eta(), mode, outgoing_at(mirror_z(wo), true, &scratch));
    return Rgb(0.0f);
}

float GltfBsdf::pdf_w(const Vec3& wo, const Vec3& wi) const {
    if (m_lambert) return same_side(wo, wi) ? std::fabs(wi.z) * k_inv_pi : 0.0f;
    Outgoing scratch;
    if (wo.z > 0.0f) return pdf_upper(wo, wi, m_eta, outgoing_at(wo, false, &scratch));
    if (wo.z < 0.0f)
        return pdf_upper(mirror_z(wo), mirror_z(wi), below_eta(), outgoing_at(mirror_z(wo), true, &scratch));
    return 0.0f;
}

bool GltfBsdf::sample(const Vec3& wo_in, float u_lobe, float u1, float u2, BsdfSample* out, TransportMode mode) const {
    if (wo_in.z == 0.0f) return false;
    bool flipped = wo_in.z < 0.0f;
    if (m_lambert) {
        // f cos / pdf = (base / pi) cos / (cos / pi) = base.
        Vec3 wi = lambert_sample(u1, u2);
        if (!(wi.z > 0.0f)) return false;
        out->wi = flipped ? mirror_z(wi) : wi;
        out->pdf_w = wi.z * k_inv_pi;
        out->weight = m_base;
        out->delta = false;
        return true;
    }
    Vec3 wo = flipped ? mirror_z(wo_in) : wo_in;
    float eta = flipped ? below_eta() : m_eta;
    Outgoing scratch;
    const Outgoing& o = outgoing_at(wo, flipped, &scratch);
    const LobeProbabilities& p = o.p;
    Vec3 wi;
    float u = u_lobe;
    bool delta_done = false;
    if (u < p.coat) {
        if (m_coat_tilted && m_coat_delta) {
            if (!coat_mirror_sample(wo, o, out)) return false;
            delta_done = true;
        } else if (m_coat_delta) {
            mirror_sample(wo, eta, o, out);
            delta_done = true;
        } else if (m_coat_tilted) {
            Vec3 wo_c = o.coat_frame.to_local(wo);
            if (!(wo_c.z > 0.0f)) return false;
            Vec3 wi_c = reflect(wo_c, ggx_sample_visible_normal(wo_c, m_coat_alpha, u1, u2));
            if (wi_c.z <= 0.0f) return false;
            wi = o.coat_frame.to_world(wi_c);
            if (wi.z <= 0.0f) return false;
        } else {
            wi = reflect(wo, ggx_sample_visible_normal(wo, m_coat_alpha, u1, u2));
            if (wi.z <= 0.0f) return false;
        }
    } else if ((u -= p.coat) < p.spec) {
        if (m_delta) {
            mirror_sample(wo, eta, o, out);
            delta_done = true;
        } else {
            wi = reflect(wo, ggx_sample_visible_normal(wo, m_alpha, u1, u2));
            if (wi.z <= 0.0f) return false;  // shadowed: not a transmission, which pdf_upper would assume
        }
    } else if ((u -= p.spec) < p.cosine) {
        wi = lambert_sample(u1, u2);
    } else {
        u -= p.cosine;
        if (!(p.trans > 0.0f)) return false;
        float u_choice = clamp(u / p.trans, 0.0f, 1.0f);
        if (m_delta) {
            float fr = fresnel_dielectric(wo.z, eta);
            if (u_choice < fr) {
                mirror_sample(wo, eta, o, out);
                delta_done = true;
            } else {
                if (m_thin)
                    wi = -wo;  // in and straight out again
                else if (!refract(wo, Vec3(0, 0, 1), eta, &wi))
                    return false;
                float scale = mode == TransportMode::Radiance && !m_thin ? 1.0f / (eta * eta) : 1.0f;
                // f cos / pdf = w_trans (1 - F) base scale / (p_trans (1 - F)), dimmed by the layers.
                out->weight =
                    m_base * (m_w_trans * scale * base_scale(o, -wi.z, std::max(0.0f, -coat_cos(wi, o))) / p.trans);
                out->pdf_w = p.trans * (1.0f - fr);
                out->wi = wi;
                out->delta = true;
                delta_done = true;
            }
        } else {
            bool transmitted;
            if (m_thin ? !thin_dielectric_sample(wo, m_alpha, eta, u_choice, u1, u2, &wi, &transmitted)
                       : !dielectric_sample(wo, m_alpha, eta, u_choice, u1, u2, &wi, &transmitted))
                return false;
        }
    }
    if (delta_done) {
        // A delta event filled *out in the (possibly mirrored) local frame; map it back.
        if (flipped) out->wi = mirror_z(out->wi);
        return true;
    }
    if (wi.z == 0.0f) return false;
    out->delta = false;
    out->pdf_w = pdf_upper(wo, wi, eta, o);
    if (!(out->pdf_w > 0.0f)) return false;
    out->weight = eval_upper(wo, wi, eta, mode, o) * (std::fabs(wi.z) / out->pdf_w);
    out->wi = flipped ? mirror_z(wi) : wi;
    return true;
}

}  // namespace veach
