#include "integrators/bdpt/mis_weight.h"

#include <cmath>

#include "integrators/bdpt/vertex_densities.h"

namespace veach {

namespace {

// Calls add(family of (s', t'), p(s', t')^2 / p(s, t)^2) for every other strategy that could have
// made the path: camera side first, then light side, each from the connection outward.
template <class Add>
void for_each_ratio(const LightSet& lights, const CameraModel& camera_model, const std::vector<PathVertex>& light,
                    int s, const std::vector<PathVertex>& camera, int t, const PathVertex* sampled_light, Add&& add) {
    // The vertices at the connection, whose pdf_rev depend on the strategy.
    const PathVertex* y = s > 0 ? (s == 1 && sampled_light ? sampled_light : &light[s - 1]) : nullptr;
    const PathVertex* y_prev = s > 1 ? &light[s - 2] : nullptr;
    const PathVertex* z = &camera[t - 1];
    const PathVertex* z_prev = t > 1 ? &camera[t - 2] : nullptr;

    float z_rev = 0, z_prev_rev = 0, y_rev = 0, y_prev_rev = 0;
    if (s == 0) {
        z_rev = light_origin_pdf_a(lights, *z, z_prev ? normalize(z_prev->p - z->p) : Vec3(0, 0, 1));
        if (z_prev) {
            z_prev_rev = light_emission_pdf_area(lights, *z, *z_prev);  // z as the origin of a light subpath
        }
    } else {
        if (t > 1) {
            if (s == 1) {
                z_rev = light_emission_pdf_area(lights, *y, *z);
            } else {
                Vec3 wo = normalize(y_prev->p - y->p), wi = normalize(z->p - y->p);
                z_rev = to_area_density(y->bsdf.pdf_w(wo, wi), *y, *z);
            }
            Vec3 wo = normalize(y->p - z->p), wi = normalize(z_prev->p - z->p);
            z_prev_rev = to_area_density(z->bsdf.pdf_w(wo, wi), *z, *z_prev);
        }
        if (t == 1) {
            y_rev = to_area_density(camera_model.pdf_dir_w(normalize(y->p - z->p)), *z, *y);
        } else {
            Vec3 wo = normalize(z_prev->p - z->p), wi = normalize(y->p - z->p);
            y_rev = to_area_density(z->bsdf.pdf_w(wo, wi), *z, *y);
        }
        if (y_prev) {
            Vec3 wo = normalize(z->p - y->p), wi = normalize(y_prev->p - y->p);
            y_prev_rev = to_area_density(y->bsdf.pdf_w(wo, wi), *y, *y_prev);
        }
    }

    // Camera side: strategies that would have made more of the path from the light.
    double r = 1.0;
    for (int i = t - 1; i > 0; --i) {
        float rev = i == t - 1 ? z_rev : (i == t - 2 ? z_prev_rev : camera[i].pdf_rev);
        r *= remap0(rev) / remap0(camera[i].pdf_fwd);
        // (s, t) = (1, 1) from the environment is never sampled: the camera sees it only by s = 0.
        bool unsampled = s == 0 && t == 2 && camera[1].infinite;
        if (!camera[i].delta && !camera[i - 1].delta && !unsampled) add(strategy_family_index(s + t - i, i), r * r);
    }
    // Light side: strategies that would have made more of the path from the camera.
    r = 1.0;
    for (int i = s - 1; i >= 0; --i) {
        const PathVertex& v = (i == 0 && s == 1 && sampled_light) ? *sampled_light : light[i];
        float rev = i == s - 1 ? y_rev : (i == s - 2 ? y_prev_rev : v.pdf_rev);
        r *= remap0(rev) / remap0(v.pdf_fwd);
        bool delta_before = i > 0 ? light[i - 1].delta : v.delta_light;
        if (!v.delta && !delta_before) add(strategy_family_index(i, s + t - i), r * r);
    }
}

}  // namespace

float mis_weight(const LightSet& lights, const CameraModel& camera_model, const std::vector<PathVertex>& light, int s,
                 const std::vector<PathVertex>& camera, int t, const PathVertex* sampled_light,
                 StrategyMask strategies) {
    double sum = 0.0;
    if (strategies == k_all_strategies) {
        for_each_ratio(lights, camera_model, light, s, camera, t, sampled_light, [&](int, double r2) { sum += r2; });
    } else {
        for_each_ratio(lights, camera_model, light, s, camera, t, sampled_light, [&](int family, double r2) {
            if ((strategies >> family) & 1u) sum += r2;
        });
    }
    return static_cast<float>(1.0 / (1.0 + sum));
}

void mis_ratio_sums(const LightSet& lights, const CameraModel& camera_model, const std::vector<PathVertex>& light,
                    int s, const std::vector<PathVertex>& camera, int t, const PathVertex* sampled_light,
                    double squares[k_strategy_families], double cubes[k_strategy_families]) {
    for (int f = 0; f < k_strategy_families; ++f) squares[f] = cubes[f] = 0.0;
    for_each_ratio(lights, camera_model, light, s, camera, t, sampled_light, [&](int family, double r2) {
        squares[family] += r2;
        cubes[family] += r2 * std::sqrt(r2);
    });
}

}  // namespace veach
