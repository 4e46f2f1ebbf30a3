#include "materials/gltf_material.h"

#include "materials/lambert_diffuse.h"
#include "materials/microfacet_ggx.h"
#include "materials/texture_sampling.h"

namespace veach {
namespace {

Rgba lookup(const TextureRef& ref, const Scene& scene, const SurfaceAttributes& attr) {
    const Texture& tex = scene.textures[static_cast<size_t>(ref.texture)];
    Vec2 uv = attr.uv[ref.texcoord == 1 ? 1 : 0];
    return sample_texture(tex, apply_uv_transform(ref.transform, uv));
}

inline float schlick_weight(float cos_theta) {
    float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
    float m2 = m * m;
    return m2 * m2 * m;
}

}  // namespace

Rgb evaluate_emission(const Material& m, const Scene& scene, const SurfaceAttributes& attr) {
    Rgb e = m.emission;
    if (m.emissive_texture.valid() && !e.is_black()) {
        Rgba t = lookup(m.emissive_texture, scene, attr);
        e *= t.rgb();
    }
    return e;
}

ShadingInputs evaluate_material(const Material& m, const Scene& scene, const SurfaceAttributes& attr) {
    ShadingInputs s;
    Rgb base = m.base_color * attr.color.rgb();
    float alpha = m.base_alpha * attr.color.a;
    if (m.base_color_texture.valid()) {
        Rgba t = lookup(m.base_color_texture, scene, attr);
        base *= t.rgb();
        alpha *= t.a;
    }
    s.base_color = base;
    s.opacity = alpha;
    float metallic = m.metallic, roughness = m.roughness;
    if (m.metallic_roughness_texture.valid()) {
        Rgba t = lookup(m.metallic_roughness_texture, scene, attr);
        roughness *= t.g;
        metallic *= t.b;
    }
    s.metallic = clamp(metallic, 0.0f, 1.0f);
    roughness = clamp(roughness, 0.0f, 1.0f);
    s.alpha = std::max(roughness * roughness, k_min_ggx_alpha);

    float specular = m.specular;
    Rgb specular_color = m.specular_color;
    if (m.specular_texture.valid()) specular *= lookup(m.specular_texture, scene, attr).a;
    if (m.specular_color_texture.valid()) specular_color *= lookup(m.specular_color_texture, scene, attr).rgb();
    float r = (m.ior - 1.0f) / (m.ior + 1.0f);
    float f0_ior = std::isfinite(r) ? r * r : 0.04f;
    Rgb f0 = f0_ior * specular_color;
    s.dielectric_f0 = Rgb(std::min(f0.r, 1.0f), std::min(f0.g, 1.0f), std::min(f0.b, 1.0f)) * specular;
    s.dielectric_f90 = specular;
    s.emission = evaluate_emission(m, scene, attr);
    return s;
}

GltfBsdf::GltfBsdf(const ShadingInputs& in)
    : m_base(in.base_color), m_metallic(in.metallic), m_alpha(in.alpha), m_f0(in.dielectric_f0),
      m_f90(in.dielectric_f90) {
    m_diffuse_weight = m_base * (1.0f - m_metallic);
    m_black = m_base.is_black() && (m_metallic >= 1.0f || (m_f0.is_black() && m_f90 == 0.0f));
    m_delta_specular = m_alpha < k_delta_alpha;
}

Rgb GltfBsdf::eval(const Vec3& wo, const Vec3& wi) const {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Rgb(0.0f);
    Vec3 h = wo + wi;
    float hl = length(h);
    if (!(hl > 0.0f)) return Rgb(0.0f);
    h = h / hl;
    float cos_vh = std::fabs(dot(wo, h));
    float fw = schlick_weight(cos_vh);
    float spec = m_delta_specular ? 0.0f : ggx_d(h, m_alpha) * ggx_g2(wo, wi, m_alpha) / (4.0f * wo.z * wi.z);

    Rgb f_metal = m_base + (Rgb(1.0f) - m_base) * fw;
    Rgb f_diel = m_f0 + (Rgb(m_f90) - m_f0) * fw;
    Rgb dielectric = m_diffuse_weight * ((1.0f - f_diel.max()) * k_inv_pi) + f_diel * ((1.0f - m_metallic) * spec);
    return f_metal * (m_metallic * spec) + dielectric;
}

// How often to sample the specular lobe: its Fresnel weight at normal-ish incidence against the
// diffuse albedo left over. Depends on wo only, so pdf_w(wo, wi) stays cheap.
float GltfBsdf::specular_probability(const Vec3& wo) const {
    float fw = schlick_weight(wo.z);
    float spec_metal = m_metallic * (m_base + (Rgb(1.0f) - m_base) * fw).average();
    Rgb f_diel = m_f0 + (Rgb(m_f90) - m_f0) * fw;
    float spec_diel = (1.0f - m_metallic) * f_diel.average();
    float diffuse = m_diffuse_weight.average() * (1.0f - f_diel.max());
    float spec = spec_metal + spec_diel;
    float total = spec + diffuse;
    if (!(total > 0.0f)) return 0.5f;
    // Never let a lobe with weight starve entirely: keeps the variance bounded.
    float p = spec / total;
    if (spec > 0.0f) p = std::max(p, 0.05f);
    if (diffuse > 0.0f) p = std::min(p, 0.95f);
    return p;
}

float GltfBsdf::pdf_w(const Vec3& wo, const Vec3& wi) const {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float p_spec = specular_probability(wo);
    float pdf = 0.0f;
    if (p_spec > 0.0f && !m_delta_specular) {
        Vec3 h = normalize(wo + wi);
        pdf += p_spec * ggx_reflection_pdf_w(wo, h, m_alpha);
    }
    if (p_spec < 1.0f) pdf += (1.0f - p_spec) * lambert_pdf_w(wo, wi);
    return pdf;
}

bool GltfBsdf::sample(const Vec3& wo, float u_lobe, float u1, float u2, BsdfSample* out) const {
    if (wo.z <= 0.0f) return false;
    float p_spec = specular_probability(wo);
    if (u_lobe < p_spec) {
        if (m_delta_specular) {
            // Perfect mirror: f = F delta(wi - reflect(wo)) / cos, so f cos / pdf = F / p_spec.
            out->wi = Vec3(-wo.x, -wo.y, wo.z);
            float fw = schlick_weight(wo.z);
            Rgb f_metal = m_base + (Rgb(1.0f) - m_base) * fw;
            Rgb f_diel = m_f0 + (Rgb(m_f90) - m_f0) * fw;
            out->weight = (f_metal * m_metallic + f_diel * (1.0f - m_metallic)) / p_spec;
            out->pdf_w = p_spec;
            out->delta = true;
            return true;
        }
        Vec3 h = ggx_sample_visible_normal(wo, m_alpha, u1, u2);
        out->wi = reflect(wo, h);
    } else {
        out->wi = lambert_sample(u1, u2);
    }
    if (out->wi.z <= 0.0f) return false;
    out->delta = false;
    out->pdf_w = pdf_w(wo, out->wi);
    if (!(out->pdf_w > 0.0f)) return false;
    out->weight = eval(wo, out->wi) * (out->wi.z / out->pdf_w);
    return true;
}

}  // namespace veach
