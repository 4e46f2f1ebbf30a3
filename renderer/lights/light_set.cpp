#include "lights/light_set.h"

#include "accel/embree_accel.h"
#include "materials/gltf_material.h"

namespace veach {

float SpotLightData::falloff_at(float cos_theta) const {
    if (cos_theta <= cos_outer) return 0.0f;
    if (falloff == SpotFalloff::Blender) {
        // Cycles 3.4: the cosine to the axis times a smoothstep over the blend region.
        float t = cos_theta - cos_outer;
        float s = (smooth > 0.0f && t < smooth) ? smoothstep01(t / smooth) : 1.0f;
        return cos_theta * s;
    }
    // glTF's recommended falloff: a squared linear ramp from the outer to the inner cone.
    float scale = 1.0f / std::max(1e-3f, cos_inner - cos_outer);
    float a = clamp((cos_theta - cos_outer) * scale, 0.0f, 1.0f);
    return a * a;
}

LightSet::LightSet(const Scene& scene, const Accel& accel) : m_scene(scene) {
    Bounds3 b = scene.bounds();
    m_scene_center = b.empty() ? Vec3() : b.center();
    m_scene_radius = b.empty() ? 1.0f : std::max(1e-6f, 0.5f * length(b.diagonal()));

    // Powers in double: pi R^2 E of a sun over a scene 1e18 across overflows a float, and an
    // infinite weight would leave every light unselectable. Only their ratios matter.
    std::vector<double> power;
    m_first_emitter.assign(scene.instances.size(), -1);
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        const Mesh& mesh = scene.meshes[inst.mesh];
        const Material& mat = scene.material_of(mesh);
        if (!mat.is_emissive() || mesh.triangle_count() == 0) continue;
        m_first_emitter[i] = static_cast<int64_t>(m_lights.size());
        for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
            TriangleLight tl;
            tl.instance = static_cast<uint32_t>(i);
            tl.prim = t;
            Vec3 p0, p1, p2;
            accel.triangle_world(tl.instance, t, &p0, &p1, &p2);
            tl.p0 = p0;
            tl.e1 = p1 - p0;
            tl.e2 = p2 - p0;
            Vec3 c = cross(tl.e1, tl.e2);
            float len = length(c);
            tl.area = 0.5f * len;
            tl.n = len > 0.0f ? c / len : Vec3(0, 0, 1);
            tl.two_sided = mat.double_sided;
            tl.textured = mat.emissive_texture.valid();
            tl.radiance = mat.emission;
            double p = double(tl.area) * mat.emission.average() * k_pi * (tl.two_sided ? 2.0 : 1.0);
            power.push_back(std::isfinite(p) && tl.area > 0.0f ? p : 0.0f);
            m_lights.emplace_back(tl);
        }
    }
    for (const PunctualLight& pl : scene.lights) {
        switch (pl.type) {
            case LightType::Point: {
                PointLightData d{pl.position, pl.intensity};
                power.push_back(4.0 * k_pi * pl.intensity.average());
                m_lights.emplace_back(d);
                break;
            }
            case LightType::Spot: {
                SpotLightData d;
                d.position = pl.position;
                d.axis = normalize(pl.direction);
                d.intensity = pl.intensity;
                d.cos_outer = pl.cos_outer;
                d.cos_inner = pl.cos_inner;
                d.smooth = (1.0f - pl.cos_outer) * pl.blend;
                d.falloff = pl.falloff;
                // The cone's solid angle bounds the emitted power.
                power.push_back(2.0 * k_pi * (1.0 - pl.cos_outer) * pl.intensity.average());
                m_lights.emplace_back(d);
                break;
            }
            case LightType::Directional: {
                DirectionalLightData d{normalize(pl.direction), pl.intensity};
                power.push_back(k_pi * double(m_scene_radius) * m_scene_radius * pl.intensity.average());
                m_lights.emplace_back(d);
                break;
            }
        }
    }
    if (scene.environment.enabled) {
        EnvironmentLight env(scene.environment);
        // The power that crosses the scene's bounding disc: pi R^2 times radiance over the sphere.
        power.push_back(k_pi * double(m_scene_radius) * m_scene_radius * env.radiance_integral());
        m_environment = static_cast<int64_t>(m_lights.size());
        m_lights.emplace_back(std::move(env));
    }
    double largest = 0;
    for (double p : power)
        if (std::isfinite(p)) largest = std::max(largest, p);
    std::vector<float> weights(power.size());
    for (size_t i = 0; i < power.size(); ++i)
        weights[i] = largest > 0 && std::isfinite(power[i]) ? float(power[i] / largest) : 0.0f;
    m_select = Distribution1D(weights);
}

Rgb LightSet::environment_radiance(const Vec3& w) const {
    if (m_environment < 0) return Rgb(0.0f);
    return std::get<EnvironmentLight>(m_lights[static_cast<size_t>(m_environment)]).radiance(w);
}

float LightSet::environment_pdf_w(const Vec3& w) const {
    if (m_environment < 0) return 0.0f;
    const auto& env = std::get<EnvironmentLight>(m_lights[static_cast<size_t>(m_environment)]);
    return m_select.pmf(static_cast<size_t>(m_environment)) * env.pdf_w(w);
}

Rgb LightSet::triangle_radiance(const TriangleLight& tl, const Vec3& w, const Rgb& emitted) const {
    float c = dot(w, tl.n);
    if (c > 0.0f || (tl.two_sided && c < 0.0f)) return emitted;
    return Rgb(0.0f);
}

Rgb LightSet::emitted_radiance(const TriangleLight& tl, Vec2 b) const {
    if (!tl.textured) return tl.radiance;
    // The emissive texture at barycentrics (b1, b2) of the triangle.
    const Mesh& mesh = m_scene.meshes[m_scene.instances[tl.instance].mesh];
    const uint32_t* idx = &mesh.indices[static_cast<size_t>(tl.prim) * 3];
    SurfaceAttributes attr;
    interpolate_uvs(mesh, idx, 1.0f - b.x - b.y, b.x, b.y, &attr);
    return evaluate_emission(m_scene.material_of(mesh), m_scene, attr);
}

bool LightSet::sample_direct(const Vec3& receiver, float u_select, float u1, float u2, LightSample* out) const {
    float pmf;
    size_t index = m_select.sample(u_select, &pmf);
    if (!(pmf > 0.0f)) return false;
    out->light = static_cast<uint32_t>(index);
    const LightVariant& lv = m_lights[index];
    if (const auto* tl = std::get_if<TriangleLight>(&lv)) {
        Vec2 b = sample_uniform_triangle(u1, u2);
        Vec3 p = tl->p0 + tl->e1 * b.x + tl->e2 * b.y;
        Vec3 d = p - receiver;
        float dist2 = length_squared(d);
        if (!(dist2 > 0.0f)) return false;
        float dist = std::sqrt(dist2);
        Vec3 wi = d / dist;
        float cos_light = -dot(wi, tl->n);
        if (!(cos_light > 0.0f) && !(tl->two_sided && cos_light < 0.0f)) return false;
        Rgb emitted = emitted_radiance(*tl, b);
        out->radiance = emitted;
        out->wi = wi;
        out->point = p;
        out->distance = dist;
        out->pdf_w = pmf * dist2 / (std::fabs(cos_light) * tl->area);
        out->is_delta = false;
        out->is_infinite = false;
        return std::isfinite(out->pdf_w) && out->pdf_w > 0.0f;
    }
    if (const auto* pl = std::get_if<PointLightData>(&lv)) {
        Vec3 d = pl->position - receiver;
        float dist2 = length_squared(d);
        if (!(dist2 > 0.0f)) return false;
        float dist = std::sqrt(dist2);
        out->wi = d / dist;
        out->point = pl->position;
        out->distance = dist;
        // Radiance-like quantity: I / r^2 is the irradiance normal to wi; with pdf = pmf the
        // estimator f cos I / (r^2 pmf) is exact.
        out->radiance = pl->intensity / dist2;
        out->pdf_w = pmf;
        out->is_delta = true;
        out->is_infinite = false;
        return true;
    }
    if (const auto* sl = std::get_if<SpotLightData>(&lv)) {
        Vec3 d = sl->position - receiver;
        float dist2 = length_squared(d);
        if (!(dist2 > 0.0f)) return false;
        float dist = std::sqrt(dist2);
        out->wi = d / dist;
        float f = sl->falloff_at(dot(-out->wi, sl->axis));
        if (!(f > 0.0f)) return false;
        out->point = sl->position;
        out->distance = dist;
        out->radiance = sl->intensity * (f / dist2);
        out->pdf_w = pmf;
        out->is_delta = true;
        out->is_infinite = false;
        return true;
    }
    if (const auto* env = std::get_if<EnvironmentLight>(&lv)) {
        float pdf_dir;
        out->wi = env->sample(u1, u2, &pdf_dir);
        if (!(pdf_dir > 0.0f)) return false;
        out->distance = k_infinity;
        out->point = receiver + out->wi * (4.0f * m_scene_radius + length(receiver - m_scene_center));
        out->radiance = env->radiance(out->wi);
        out->pdf_w = pmf * pdf_dir;
        out->is_delta = false;
        out->is_infinite = true;
        return std::isfinite(out->pdf_w) && !out->radiance.is_black();
    }
    const auto& dl = std::get<DirectionalLightData>(lv);
    out->wi = -dl.direction;
    out->distance = k_infinity;
    out->point = receiver + out->wi * (4.0f * m_scene_radius + length(receiver - m_scene_center));
    out->radiance = dl.irradiance;
    out->pdf_w = pmf;
    out->is_delta = true;
    out->is_infinite = true;
    return true;
}

namespace {
// Emission from a triangle: one side (or both, chosen evenly, for double-sided materials),
// cosine-weighted around the side's normal.
float triangle_dir_pdf(const TriangleLight& tl, const Vec3& dir) {
    float c = dot(dir, tl.n);
    if (!tl.two_sided && c <= 0.0f) return 0.0f;
    float pdf = std::fabs(c) * k_inv_pi;
    return tl.two_sided ? 0.5f * pdf : pdf;
}
}  // namespace

bool LightSet::is_delta_position(size_t light) const {
    return std::holds_alternative<PointLightData>(m_lights[light]) ||
           std::holds_alternative<SpotLightData>(m_lights[light]);
}

bool LightSet::sample_emission(float u_select, float u1, float u2, float u3, float u4, LightEmission* out) const {
    float pmf, u_side = 0.0f;
    size_t index = m_select.sample(u_select, &pmf, &u_side);
    if (!(pmf > 0.0f)) return false;
    out->light = static_cast<uint32_t>(index);
    const LightVariant& lv = m_lights[index];
    if (const auto* tl = std::get_if<TriangleLight>(&lv)) {
        Vec2 b = sample_uniform_triangle(u1, u2);
        out->point = tl->p0 + tl->e1 * b.x + tl->e2 * b.y;
        Vec3 n = tl->n;
        if (tl->two_sided && u_side < 0.5f) n = -n;
        Vec3 local = sample_cosine_hemisphere(u3, u4);
        out->dir = Frame(n).to_world(local);
        out->normal = n;
        Rgb emitted = emitted_radiance(*tl, b);
        out->value = emitted;
        out->pdf_pos_a = 1.0f / tl->area;
        out->pdf_dir_w = triangle_dir_pdf(*tl, out->dir);
        out->delta_position = out->delta_direction = false;
        return tl->area > 0.0f && out->pdf_dir_w > 0.0f;
    }
    out->normal = Vec3(0, 0, 0);
    if (const auto* pl = std::get_if<PointLightData>(&lv)) {
        out->point = pl->position;
        out->dir = sample_uniform_sphere(u3, u4);
        out->value = pl->intensity;
        out->pdf_pos_a = 1.0f;
        out->pdf_dir_w = k_inv_four_pi;
        out->delta_position = true;
        out->delta_direction = false;
        return true;
    }
    if (const auto* sl = std::get_if<SpotLightData>(&lv)) {
        out->point = sl->position;
        out->dir = Frame(sl->axis).to_world(sample_uniform_cone(u3, u4, sl->cos_outer));
        float f = sl->falloff_at(dot(out->dir, sl->axis));
        out->value = sl->intensity * f;
        out->pdf_pos_a = 1.0f;
        out->pdf_dir_w = 1.0f / (2.0f * k_pi * (1.0f - sl->cos_outer));
        out->delta_position = true;
        out->delta_direction = false;
        return f > 0.0f && std::isfinite(out->pdf_dir_w);
    }
    if (const auto* env = std::get_if<EnvironmentLight>(&lv)) {
        // A direction toward the environment from its map density, then parallel rays along the
        // opposite direction through a disc covering the scene's bounding sphere, outside it
        // (pbrt-v3 section 16.1.2): pdf_pos_a = 1 / (pi R^2).
        float pdf_dir;
        Vec3 w = env->sample(u1, u2, &pdf_dir);
        if (!(pdf_dir > 0.0f)) return false;
        Frame frame(-w);
        Vec2 d = sample_concentric_disk(u3, u4);
        out->point = m_scene_center + (frame.s * d.x + frame.t * d.y) * m_scene_radius + w * m_scene_radius;
        out->dir = -w;
        out->value = env->radiance(w);
        out->pdf_pos_a = 1.0f / (k_pi * m_scene_radius * m_scene_radius);
        out->pdf_dir_w = pdf_dir;
        out->delta_position = out->delta_direction = false;
        return std::isfinite(pdf_dir) && !out->value.is_black();
    }
    const auto& dl = std::get<DirectionalLightData>(lv);
    // Parallel rays through a disc that covers the scene's bounding sphere, placed outside it.
    Frame frame(dl.direction);
    Vec2 d = sample_concentric_disk(u3, u4);
    out->point = m_scene_center + (frame.s * d.x + frame.t * d.y) * m_scene_radius - dl.direction * m_scene_radius;
    out->dir = dl.direction;
    out->value = dl.irradiance;
    out->pdf_pos_a = 1.0f / (k_pi * m_scene_radius * m_scene_radius);
    out->pdf_dir_w = 1.0f;
    out->delta_position = false;
    out->delta_direction = true;
    return true;
}

void LightSet::pdf_emission(size_t light, const Vec3& dir, float* pdf_pos_a, float* pdf_dir_w) const {
    const LightVariant& lv = m_lights[light];
    if (const auto* tl = std::get_if<TriangleLight>(&lv)) {
        *pdf_pos_a = tl->area > 0.0f ? 1.0f / tl->area : 0.0f;
        *pdf_dir_w = triangle_dir_pdf(*tl, dir);
    } else if (std::holds_alternative<PointLightData>(lv)) {
        *pdf_pos_a = 1.0f;
        *pdf_dir_w = k_inv_four_pi;
    } else if (const auto* sl = std::get_if<SpotLightData>(&lv)) {
        *pdf_pos_a = 1.0f;
        *pdf_dir_w = dot(dir, sl->axis) > sl->cos_outer ? 1.0f / (2.0f * k_pi * (1.0f - sl->cos_outer)) : 0.0f;
    } else if (const auto* env = std::get_if<EnvironmentLight>(&lv)) {
        *pdf_pos_a = 1.0f / (k_pi * m_scene_radius * m_scene_radius);
        *pdf_dir_w = env->pdf_w(-dir);  // dir is the way the particle travels, away from the sky
    } else {
        *pdf_pos_a = 1.0f / (k_pi * m_scene_radius * m_scene_radius);
        *pdf_dir_w = 1.0f;
    }
}

float LightSet::pdf_direct_w(size_t light, const Vec3& receiver, const Vec3& p) const {
    const auto* tl = std::get_if<TriangleLight>(&m_lights[light]);
    if (!tl) return 0.0f;
    Vec3 d = p - receiver;
    float dist2 = length_squared(d);
    float cos_light = std::fabs(dot(d, tl->n)) / std::sqrt(dist2);
    if (!(cos_light > 0.0f) || !(tl->area > 0.0f)) return 0.0f;
    return m_select.pmf(light) * dist2 / (cos_light * tl->area);
}

}  // namespace veach
