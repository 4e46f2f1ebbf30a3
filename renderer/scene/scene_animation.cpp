#include "scene/scene_animation.h"

#include <algorithm>
#include <cmath>

#include "scene/light_units.h"
#include "scene/scene.h"

namespace veach {
namespace {

// The key interval holding t: t in [times[k], times[k+1]], s its fraction. Outside the input
// range the end keys hold (k and k+1 the same key, s = 0).
struct Interval {
    size_t k0 = 0, k1 = 0;
    double s = 0, dt = 0;
};

Interval locate(const std::vector<float>& times, double t) {
    Interval in;
    size_t n = times.size();
    if (n == 0 || !(t > times.front())) return in;  // also NaN: the first key
    if (t >= times.back()) {
        in.k0 = in.k1 = n - 1;
        return in;
    }
    size_t k1 = size_t(std::upper_bound(times.begin(), times.end(), float(t)) - times.begin());
    // float(t) may round past t; the comparisons below stay in double.
    while (k1 > 1 && double(times[k1 - 1]) > t) --k1;
    while (k1 < n - 1 && double(times[k1]) <= t) ++k1;
    in.k0 = k1 - 1;
    in.k1 = k1;
    in.dt = double(times[k1]) - double(times[k1 - 1]);
    in.s = in.dt > 0 ? (t - double(times[k1 - 1])) / in.dt : 0.0;
    return in;
}

struct Mat3 {
    double m[3][3];
};

// The cofactor matrix: (M^-1)^T up to the factor 1/det, which the normalisation removes; unlike
// the inverse it exists for singular M too.
Mat3 cofactor(const Transform& t) {
    const auto& a = t.m;
    Mat3 c;
    c.m[0][0] = double(a[1][1]) * a[2][2] - double(a[1][2]) * a[2][1];
    c.m[0][1] = double(a[1][2]) * a[2][0] - double(a[1][0]) * a[2][2];
    c.m[0][2] = double(a[1][0]) * a[2][1] - double(a[1][1]) * a[2][0];
    c.m[1][0] = double(a[0][2]) * a[2][1] - double(a[0][1]) * a[2][2];
    c.m[1][1] = double(a[0][0]) * a[2][2] - double(a[0][2]) * a[2][0];
    c.m[1][2] = double(a[0][1]) * a[2][0] - double(a[0][0]) * a[2][1];
    c.m[2][0] = double(a[0][1]) * a[1][2] - double(a[0][2]) * a[1][1];
    c.m[2][1] = double(a[0][2]) * a[1][0] - double(a[0][0]) * a[1][2];
    c.m[2][2] = double(a[0][0]) * a[1][1] - double(a[0][1]) * a[1][0];
    return c;
}

Vec3 apply(const Mat3& c, const Vec3& v) {
    return Vec3(float(c.m[0][0] * v.x + c.m[0][1] * v.y + c.m[0][2] * v.z),
                float(c.m[1][0] * v.x + c.m[1][1] * v.y + c.m[1][2] * v.z),
                float(c.m[2][0] * v.x + c.m[2][1] * v.y + c.m[2][2] * v.z));
}

// A unit vector, or `fallback` when v has no direction.
Vec3 unit_or(const Vec3& v, const Vec3& fallback) {
    float len = length(v);
    return len > 0 && std::isfinite(len) ? v / len : fallback;
}

Transform scaled(const Transform& t, float w) {
    Transform r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = t.m[i][j] * w;
    return r;
}

void accumulate(Transform& sum, const Transform& t, float w) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) sum.m[i][j] += t.m[i][j] * w;
}

PunctualLight place_light(const LocalLight& l, const Transform& world) {
    PunctualLight light = *l.local;
    light.position = world.point(l.local->position);
    light.direction = unit_or(world.vector(l.local->direction), l.local->direction);
    if (light.type == LightType::Area) {
        light.axis_u = world.vector(l.local->axis_u);
        light.axis_v = world.vector(l.local->axis_v);
        float area = length(cross(light.axis_u, light.axis_v)) * (light.shape == AreaShape::Rectangle ? 4.0f : k_pi);
        light.radiance = area > 0 && std::isfinite(area) ? l.area_power / area : Rgb(0.0f);
    }
    return light;
}

bool finite_light(const PunctualLight& l) {
    return is_finite(l.position) && is_finite(l.direction) && is_finite(l.axis_u) && is_finite(l.axis_v) &&
           std::isfinite(l.radiance.r) && std::isfinite(l.radiance.g) && std::isfinite(l.radiance.b);
}

float clamped(float v, float lo, float hi) { return std::isfinite(v) ? std::clamp(v, lo, hi) : lo; }
Rgb clamped(const Rgb& c, float lo, float hi) { return {clamped(c.r, lo, hi), clamped(c.g, lo, hi), clamped(c.b, lo, hi)}; }

// The animated values of KHR_animation_pointer properties at a time: rest values, then every
// selected animation's channels.
struct PropertyValues {
    std::vector<MaterialRest> materials;
    std::vector<LightRest> lights;
    std::vector<CameraRest> cameras;
};

PropertyValues animated_properties(const SceneAnimation& a, double seconds) {
    PropertyValues v{a.material_rest, a.light_rest, a.camera_rest};
    for (size_t i = 0; i < a.animations.size(); ++i) {
        if (a.selected >= 0 && size_t(a.selected) != i) continue;
        const Animation& anim = a.animations[i];
        for (const PropertyChannel& pc : anim.properties) {
            float x[4] = {0, 0, 0, 0};
            sample_animation(anim.samplers[size_t(pc.sampler)], seconds, false, x);
            const size_t t = size_t(pc.target);
            MaterialRest* m = t < v.materials.size() ? &v.materials[t] : nullptr;
            LightRest* l = t < v.lights.size() ? &v.lights[t] : nullptr;
            switch (pc.property) {
                case AnimatedProperty::BaseColor:
                    if (m) m->base_color = Rgb(x[0], x[1], x[2]), m->base_alpha = x[3];
                    break;
                case AnimatedProperty::Metallic: if (m) m->metallic = x[0]; break;
                case AnimatedProperty::Roughness: if (m) m->roughness = x[0]; break;
                case AnimatedProperty::EmissiveFactor: if (m) m->emissive_factor = Rgb(x[0], x[1], x[2]); break;
                case AnimatedProperty::EmissiveStrength: if (m) m->emissive_strength = x[0]; break;
                case AnimatedProperty::AlphaCutoff: if (m) m->alpha_cutoff = x[0]; break;
                case AnimatedProperty::LightColor: if (l) l->color = Rgb(x[0], x[1], x[2]); break;
                case AnimatedProperty::LightIntensity: if (l) l->intensity = x[0]; break;
                case AnimatedProperty::SpotInnerCone: if (l) l->inner_cone = x[0]; break;
                case AnimatedProperty::SpotOuterCone: if (l) l->outer_cone = x[0]; break;
                case AnimatedProperty::CameraYfov:
                case AnimatedProperty::CameraXmag:
                case AnimatedProperty::CameraYmag:
                    for (CameraRest& c : v.cameras) {
                        if (c.source != pc.target) continue;
                        (pc.property == AnimatedProperty::CameraYfov   ? c.yfov
                         : pc.property == AnimatedProperty::CameraXmag ? c.xmag
                                                                       : c.ymag) = x[0];
                    }
                    break;
            }
        }
    }
    return v;
}

// Writes animated material factors into the scene, held to the ranges the import holds the
// file's to (factors in [0, 1], emission strength up to k_max_emission_strength), so a material
// at its rest values is bit for bit the one the import made.
void apply_material(Material& m, const MaterialRest& v) {
    Rgb base = clamped(v.base_color, 0.0f, 1.0f);
    if (v.unlit) {
        m.emission = base;  // unlit: the base colour is what is seen (gltf_materials.cpp)
    } else {
        m.base_color = base;
        m.metallic = clamped(v.metallic, 0.0f, 1.0f);
        m.roughness = clamped(v.roughness, 0.0f, 1.0f);
        m.emission =
            clamped(v.emissive_factor, 0.0f, 1.0f) * clamped(v.emissive_strength, 0.0f, k_max_emission_strength);
    }
    m.base_alpha = clamped(v.base_alpha, 0.0f, 1.0f);
    if (std::isfinite(v.alpha_cutoff)) m.alpha_cutoff = v.alpha_cutoff;  // as the import takes it
}

// The local light with animated colour, intensity and cone. An area light's power was given in
// watts by VEACH_lights_blender, not by the intensity: it is scaled by the animated colour x
// intensity over the rest one (per channel, where the rest is not black).
LocalLight relit(const LocalLight& l, const LightRest& rest, const LightRest& now) {
    if (now.color.r == rest.color.r && now.color.g == rest.color.g && now.color.b == rest.color.b &&
        now.intensity == rest.intensity && now.inner_cone == rest.inner_cone && now.outer_cone == rest.outer_cone)
        return l;
    PunctualLight light = *l.local;
    LocalLight out = l;
    Rgb color = clamped(now.color, 0.0f, 1e30f);
    float intensity = clamped(now.intensity, 0.0f, k_max_light_intensity);
    if (light.type == LightType::Area) {
        auto ratio = [&](float c, float c0) {
            float r0 = c0 * rest.intensity;
            return r0 > 0 ? c * intensity / r0 : 1.0f;
        };
        out.area_power = Rgb(l.area_power.r * ratio(color.r, rest.color.r), l.area_power.g * ratio(color.g, rest.color.g),
                             l.area_power.b * ratio(color.b, rest.color.b));
    } else {
        light.intensity = radiometric_intensity(color, intensity);
    }
    if (light.type == LightType::Spot) set_spot_cone(light, now.inner_cone, now.outer_cone);
    out.local = std::make_shared<const PunctualLight>(std::move(light));
    return out;
}

}  // namespace

int animated_property_components(AnimatedProperty p) {
    switch (p) {
        case AnimatedProperty::BaseColor: return 4;
        case AnimatedProperty::EmissiveFactor:
        case AnimatedProperty::LightColor: return 3;
        default: return 1;
    }
}

Transform NodePose::local() const {
    if (has_matrix) return matrix;
    return veach::translation(translation) * rotation_quaternion(rotation[0], rotation[1], rotation[2], rotation[3]) *
           scaling(scale);
}

void sample_animation(const AnimationSampler& s, double t, bool rotation, float* out) {
    const int c = s.components;
    const size_t keys = s.times.size();
    if (keys == 0 || c <= 0) return;
    Interval in = locate(s.times, t);
    if (s.interpolation == Interpolation::CubicSpline) {
        // Per key: in-tangent a, value v, out-tangent b, `c` floats each. Between keys k and k+1
        // (interval td, fraction u) the spec's Hermite curve, tangents scaled by td:
        // p = (2u^3 - 3u^2 + 1) v_k + td (u^3 - 2u^2 + u) b_k + (-2u^3 + 3u^2) v_k+1 + td (u^3 - u^2) a_k+1.
        const float* v0 = &s.values[(3 * in.k0 + 1) * c];
        if (in.k0 == in.k1) {
            std::copy(v0, v0 + c, out);
        } else {
            const float* b0 = &s.values[(3 * in.k0 + 2) * c];
            const float* a1 = &s.values[(3 * in.k1 + 0) * c];
            const float* v1 = &s.values[(3 * in.k1 + 1) * c];
            double u = in.s, u2 = u * u, u3 = u2 * u, td = in.dt;
            double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
            for (int i = 0; i < c; ++i)
                out[i] = float(h00 * v0[i] + td * h10 * b0[i] + h01 * v1[i] + td * h11 * a1[i]);
        }
        if (rotation && c == 4) normalise_quaternion(out);
        return;
    }
    const float* v0 = &s.values[in.k0 * c];
    if (s.interpolation == Interpolation::Step || in.k0 == in.k1) {
        std::copy(v0, v0 + c, out);
        if (rotation && c == 4) normalise_quaternion(out);
        return;
    }
    const float* v1 = &s.values[in.k1 * c];
    if (rotation && c == 4) {
        slerp_quaternion(v0, v1, in.s, out);
        return;
    }
    for (int i = 0; i < c; ++i) out[i] = float((1 - in.s) * v0[i] + in.s * v1[i]);
}

void pose_scene(Scene& scene, double seconds) {
    SceneAnimation& a = scene.animation;
    if (!a.enabled) return;
    const size_t nodes = a.rest.size();

    // Local poses and morph weights: rest values, then every selected channel.
    std::vector<NodePose> pose = a.rest;
    std::vector<std::vector<float>> weights = a.rest_weights;
    for (size_t i = 0; i < a.animations.size(); ++i) {
        if (a.selected >= 0 && size_t(a.selected) != i) continue;
        const Animation& anim = a.animations[i];
        for (const AnimationChannel& ch : anim.channels) {
            const AnimationSampler& s = anim.samplers[size_t(ch.sampler)];
            NodePose& p = pose[size_t(ch.node)];
            float v[4] = {0, 0, 0, 1};
            switch (ch.path) {
                case AnimatedPath::Translation:
                    sample_animation(s, seconds, false, v);
                    p.translation = Vec3(v[0], v[1], v[2]);
                    break;
                case AnimatedPath::Rotation:
                    sample_animation(s, seconds, true, v);
                    p.rotation = {v[0], v[1], v[2], v[3]};
                    break;
                case AnimatedPath::Scale:
                    sample_animation(s, seconds, false, v);
                    p.scale = Vec3(v[0], v[1], v[2]);
                    break;
                case AnimatedPath::Weights: {
                    std::vector<float>& w = weights[size_t(ch.node)];
                    w.assign(size_t(s.components), 0.0f);
                    sample_animation(s, seconds, false, w.data());
                    break;
                }
            }
        }
    }
    std::vector<Transform> local(nodes);
    for (size_t i = 0; i < nodes; ++i) local[i] = pose[i].local();

    // World transforms of nodes (the importer checked the parents form no cycle), for joints,
    // and of placements (a node reached twice is placed twice), for what the nodes carry.
    std::vector<Transform> node_world(nodes);
    std::vector<uint8_t> done(nodes, 0);
    std::vector<int> chain;
    for (size_t i = 0; i < nodes; ++i) {
        chain.clear();
        for (int n = int(i); n >= 0 && !done[size_t(n)]; n = a.parents[size_t(n)]) chain.push_back(n);
        for (size_t k = chain.size(); k-- > 0;) {
            int n = chain[k], parent = a.parents[size_t(n)];
            node_world[size_t(n)] = parent >= 0 ? node_world[size_t(parent)] * local[size_t(n)] : local[size_t(n)];
            done[size_t(n)] = 1;
        }
    }
    std::vector<Transform> world(a.placements.size());
    for (size_t p = 0; p < a.placements.size(); ++p) {
        const NodePlacement& pl = a.placements[p];
        world[p] = pl.parent >= 0 ? world[size_t(pl.parent)] * local[size_t(pl.node)] : local[size_t(pl.node)];
        for (size_t k = 0; k < pl.instances.size(); ++k)
            scene.instances[pl.instances[k]].object_to_world =
                pl.instance_offsets.empty() ? world[p] : world[p] * pl.instance_offsets[k];
        if (pl.camera >= 0) scene.cameras[size_t(pl.camera)].camera_to_world = world[p];
    }
    // KHR_animation_pointer properties: materials, then lights and cameras as they are placed.
    const PropertyValues values = animated_properties(a, seconds);
    for (const MaterialRest& m : values.materials)
        if (m.material >= 0 && size_t(m.material) < scene.materials.size())
            apply_material(scene.materials[size_t(m.material)], m);
    for (size_t c = 0; c < values.cameras.size() && c < scene.cameras.size(); ++c) {
        Camera& cam = scene.cameras[c];
        const CameraRest& v = values.cameras[c];
        if (v.yfov > 0.0f && v.yfov < k_pi) cam.yfov = v.yfov;  // else the last valid one stays
        if (std::isfinite(v.xmag) && v.xmag != 0.0f) cam.xmag = v.xmag;
        if (std::isfinite(v.ymag) && v.ymag != 0.0f) cam.ymag = v.ymag;
    }
    scene.lights.clear();
    for (size_t p = 0; p < a.placements.size(); ++p) {
        if (a.placements[p].light < 0) continue;
        const LocalLight& local = a.lights[size_t(a.placements[p].light)];
        const size_t source = size_t(local.source);
        PunctualLight light = local.source >= 0 && source < values.lights.size()
                                  ? place_light(relit(local, a.light_rest[source], values.lights[source]), world[p])
                                  : place_light(local, world[p]);
        if (finite_light(light)) scene.lights.push_back(std::move(light));
    }

    // Skin matrices per skin: joint world x inverse bind matrix.
    std::vector<std::vector<Transform>> joint_matrices(a.skins.size());
    for (size_t k = 0; k < a.skins.size(); ++k) {
        const SkinData& skin = a.skins[k];
        joint_matrices[k].resize(skin.joints.size());
        for (size_t j = 0; j < skin.joints.size(); ++j)
            joint_matrices[k][j] = node_world[size_t(skin.joints[j])] * skin.inverse_bind[j];
    }

    for (DeformingMesh& d : a.deforming) {
        Mesh& mesh = scene.meshes[d.mesh];
        if (!d.captured) {
            d.rest_positions = mesh.positions;
            d.rest_normals = mesh.normals;
            d.rest_tangents = mesh.tangents;
            if (d.targets)
                for (const MorphTarget& target : *d.targets) {
                    if (!target.uv0.empty()) d.rest_uv0 = mesh.uv0;
                    if (!target.uv1.empty()) d.rest_uv1 = mesh.uv1;
                    if (!target.colors.empty()) d.rest_colors = mesh.colors;
                }
            d.captured = true;
        }
        const size_t n = d.rest_positions.size();
        std::vector<Vec3>& P = mesh.positions;
        std::vector<Vec3>& N = mesh.normals;
        std::vector<Vec3>& T = mesh.tangents;
        P = d.rest_positions;
        N = d.rest_normals;
        T = d.rest_tangents;
        // Texture coordinates and colours only when a target moves them (rest_* non-empty).
        if (!d.rest_uv0.empty()) mesh.uv0 = d.rest_uv0;
        if (!d.rest_uv1.empty()) mesh.uv1 = d.rest_uv1;
        if (!d.rest_colors.empty()) mesh.colors = d.rest_colors;
        // Morph targets first, in the mesh's own space (glTF: deltas, then the skin).
        if (d.targets) {
            const std::vector<float>& w = weights[size_t(a.placements[size_t(d.placement)].node)];
            for (size_t k = 0; k < d.targets->size() && k < w.size(); ++k) {
                const MorphTarget& target = (*d.targets)[k];
                const float wk = w[k];
                if (wk == 0.0f) continue;
                if (target.positions.size() == n)
                    for (size_t i = 0; i < n; ++i) P[i] += target.positions[i] * wk;
                if (target.normals.size() == n && N.size() == n)
                    for (size_t i = 0; i < n; ++i) N[i] += target.normals[i] * wk;
                if (target.tangents.size() == n && T.size() == n)
                    for (size_t i = 0; i < n; ++i) T[i] += target.tangents[i] * wk;
                auto add_uv = [&](const std::vector<Vec2>& delta, std::vector<Vec2>& uv) {
                    if (delta.size() != n || uv.size() != n) return;
                    for (size_t i = 0; i < n; ++i) uv[i] = Vec2{uv[i].x + wk * delta[i].x, uv[i].y + wk * delta[i].y};
                };
                add_uv(target.uv0, mesh.uv0);
                add_uv(target.uv1, mesh.uv1);
                if (target.colors.size() == n && mesh.colors.size() == n)
                    for (size_t i = 0; i < n; ++i) {
                        Rgba& c = mesh.colors[i];
                        const Rgba& dc = target.colors[i];
                        c = Rgba{c.r + wk * dc.r, c.g + wk * dc.g, c.b + wk * dc.b, c.a + wk * dc.a};
                    }
            }
            for (Rgba& c : mesh.colors)
                if (!d.rest_colors.empty())
                    c = Rgba{clamped(c.r, 0.0f, 1.0f), clamped(c.g, 0.0f, 1.0f), clamped(c.b, 0.0f, 1.0f),
                             clamped(c.a, 0.0f, 1.0f)};
        }
        if (d.skin >= 0) {
            // Skinned vertices are in world space: the mesh node's own transform is ignored.
            scene.instances[d.instance].object_to_world = Transform{};
            const std::vector<Transform>& jm = joint_matrices[size_t(d.skin)];
            for (size_t i = 0; i < n; ++i) {
                Transform m = scaled(Transform{}, 0.0f);
                float total = 0;
                for (int k = 0; k < d.influences; ++k) {
                    float w = d.weights[i * size_t(d.influences) + size_t(k)];
                    if (w == 0.0f) continue;
                    accumulate(m, jm[d.joints[i * size_t(d.influences) + size_t(k)]], w);
                    total += w;
                }
                if (!(total > 0.0f)) m = Transform{};  // no influence: the vertex stays in mesh space
                P[i] = m.point(P[i]);
                if (N.size() == n) N[i] = unit_or(apply(cofactor(m), N[i]), d.rest_normals[i]);
                if (T.size() == n) T[i] = unit_or(m.vector(T[i]), d.rest_tangents[i]);
            }
        } else {
            scene.instances[d.instance].object_to_world = world[size_t(d.placement)];
            for (Vec3& v : N) v = unit_or(v, Vec3(0, 0, 1));
            for (Vec3& v : T) v = unit_or(v, Vec3(1, 0, 0));
        }
    }
}

}  // namespace veach
