#include "integrators/bdpt/vertex_densities.h"

namespace veach {

float light_origin_pdf_a(const LightSet& lights, const PathVertex& v, const Vec3& dir_out) {
    float pdf_pos, pdf_dir;
    if (lights.is_at_infinity(static_cast<size_t>(v.light)) && !v.delta_light) {
        // At infinity the origin's "area" density is that of its direction.
        lights.pdf_emission(static_cast<size_t>(v.light), v.p, v.light_dir, &pdf_pos, &pdf_dir);
        return lights.selection_pmf(static_cast<size_t>(v.light)) * pdf_dir;
    }
    lights.pdf_emission(static_cast<size_t>(v.light), v.p, dir_out, &pdf_pos, &pdf_dir);
    return lights.selection_pmf(static_cast<size_t>(v.light)) * pdf_pos;
}

float light_emission_pdf_area(const LightSet& lights, const PathVertex& light_v, const PathVertex& to) {
    if (light_v.infinite) {
        float pdf_pos, pdf_dir;
        lights.pdf_emission(static_cast<size_t>(light_v.light), light_v.p, light_v.light_dir, &pdf_pos, &pdf_dir);
        return to.has_normal ? pdf_pos * std::fabs(dot(to.ng, light_v.light_dir)) : pdf_pos;
    }
    Vec3 d = to.p - light_v.p;
    float len = length(d);
    if (!(len > 0.0f)) return 0.0f;
    float pdf_pos, pdf_dir;
    lights.pdf_emission(static_cast<size_t>(light_v.light), light_v.p, d / len, &pdf_pos, &pdf_dir);
    return to_area_density(pdf_dir, light_v, to);
}

}  // namespace veach
