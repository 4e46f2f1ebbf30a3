#include "lights/light_set.h"

#include "accel/embree_accel.h"

namespace veach {

namespace {

TriangleLight make_triangle_light(const Accel& accel, uint32_t instance, uint32_t prim, const Material& mat) {
    TriangleLight tl;
    tl.instance = instance;
    tl.prim = prim;
    Vec3 p0, p1, p2;
    accel.triangle_world(instance, prim, &p0, &p1, &p2);
    tl.p0 = p0;
    tl.e1 = p1 - p0;
    tl.e2 = p2 - p0;
    Vec3 c = cross(tl.e1, tl.e2);
    float len = length(c);
    tl.area = 0.5f * len;
    tl.n = len > 0.0f ? c / len : Vec3(0, 0, 1);
    tl.two_sided = mat.double_sided;
    tl.textured = mat.emissive_texture.valid();
    tl.radiance_value = mat.emission;
    return tl;
}

Light make_light(const PunctualLight& pl) {
    switch (pl.type) {
        case LightType::Point: return PointLight{pl.position, pl.intensity, pl.radius};
        case LightType::Spot: {
            SpotLight d;
            d.position = pl.position;
            d.axis = normalize(pl.direction);
            d.intensity = pl.intensity;
            d.cos_outer = pl.cos_outer;
            d.cos_inner = pl.cos_inner;
            d.smooth = (1.0f - pl.cos_outer) * pl.blend;
            d.falloff = pl.falloff;
            d.radius = pl.radius;
            return d;
        }
        case LightType::Directional: {
            float half = 0.5f * std::min(pl.angle, 0.999f * k_pi);  // Cycles stops short of a hemisphere too
            return DirectionalLight{normalize(pl.direction), pl.intensity, half > 0.0f ? std::tan(half) : 0.0f};
        }
        case LightType::Area:
            return AreaLight::make(pl.position, pl.axis_u, pl.axis_v, pl.direction, pl.shape, pl.radiance);
    }
    return PointLight{};
}

}  // namespace

LightSet::LightSet(const Scene& scene, const Accel& accel, const Bounds3* bounds) {
    Bounds3 b = bounds ? *bounds : scene.bounds();
    m_ctx.scene = &scene;
    m_ctx.center = b.empty() ? Vec3() : b.center();
    m_ctx.radius = b.empty() ? 1.0f : std::max(1e-6f, 0.5f * length(b.diagonal()));

    // Powers in double: pi R^2 E of a sun over a scene 1e18 across overflows a float, and an
    // infinite weight would leave every light unselectable. Only their ratios matter.
    std::vector<double> power;
    auto add = [&](Light light) {
        power.push_back(std::visit([&](const auto& l) { return l.power(m_ctx); }, light));
        m_lights.push_back(std::move(light));
    };
    m_first_emitter.assign(scene.instances.size(), -1);
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        const Mesh& mesh = scene.meshes[inst.mesh];
        const Material& mat = scene.material_of(mesh);
        if (!mat.is_emissive() || mesh.triangle_count() == 0) continue;
        m_first_emitter[i] = static_cast<int64_t>(m_lights.size());
        for (uint32_t t = 0; t < mesh.triangle_count(); ++t)
            add(make_triangle_light(accel, static_cast<uint32_t>(i), t, mat));
    }
    for (const PunctualLight& pl : scene.lights) {
        uint32_t index = static_cast<uint32_t>(m_lights.size());
        add(make_light(pl));
        const Light& l = m_lights.back();
        if (std::holds_alternative<AreaLight>(l) || (!is_delta_position(index) && !is_at_infinity(index)))
            m_shapes.push_back(index);
        if (const auto* d = std::get_if<DirectionalLight>(&l); d && !d->delta_direction()) m_infinite.push_back(index);
    }
    if (scene.environment.enabled) {
        m_environment = static_cast<int64_t>(m_lights.size());
        m_infinite.insert(m_infinite.begin(), static_cast<uint32_t>(m_environment));
        add(EnvironmentLight(scene.environment));
    }
    double largest = 0;
    for (double p : power)
        if (std::isfinite(p)) largest = std::max(largest, p);
    std::vector<float> weights(power.size());
    for (size_t i = 0; i < power.size(); ++i)
        weights[i] = largest > 0 && std::isfinite(power[i]) ? float(power[i] / largest) : 0.0f;
    m_select = Distribution1D(weights);
}

bool LightSet::sample_direct(const Vec3& receiver, float u_select, float u1, float u2, LightSample* out) const {
    float pmf;
    size_t index = m_select.sample(u_select, &pmf);
    if (!(pmf > 0.0f)) return false;
    out->light = static_cast<uint32_t>(index);
    return std::visit([&](const auto& l) { return l.sample_direct(m_ctx, receiver, u1, u2, pmf, out); },
                      m_lights[index]);
}

bool LightSet::sample_emission(float u_select, float u1, float u2, float u3, float u4, LightEmission* out) const {
    float pmf, u_side = 0.0f;
    size_t index = m_select.sample(u_select, &pmf, &u_side);
    if (!(pmf > 0.0f)) return false;
    out->light = static_cast<uint32_t>(index);
    return std::visit([&](const auto& l) { return l.sample_emission(m_ctx, u_side, u1, u2, u3, u4, out); },
                      m_lights[index]);
}

}  // namespace veach
