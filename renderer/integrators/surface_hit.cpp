#include "integrators/surface_hit.h"

namespace veach {

namespace {
// Bound on the relative error of n floating-point operations (pbrt's gamma(n)), widened for
// the instance transform applied to the vertices before interpolation.
constexpr float k_position_error_scale = 32.0f * 0x1p-24f;
}  // namespace

SurfaceHit make_surface_hit(const RenderScene& rs, const RayHit& hit) {
    const Scene& scene = rs.scene();
    SurfaceHit s;
    s.instance = hit.instance;
    s.prim = hit.prim;
    const Instance& inst = scene.instances[hit.instance];
    const Mesh& mesh = scene.meshes[inst.mesh];
    s.material = &scene.material_of(mesh);
    const uint32_t* idx = &mesh.indices[static_cast<size_t>(hit.prim) * 3];
    float b1 = hit.u, b2 = hit.v, b0 = 1.0f - b1 - b2;
    s.b1 = b1;
    s.b2 = b2;

    Vec3 p0, p1, p2;
    rs.accel().triangle_world(hit.instance, hit.prim, &p0, &p1, &p2);
    s.p = p0 * b0 + p1 * b1 + p2 * b2;
    s.p_error = (abs(p0 * b0) + abs(p1 * b1) + abs(p2 * b2)) * k_position_error_scale;

    Vec3 c = cross(p1 - p0, p2 - p0);
    float len = length(c);
    s.ng = len > 0.0f ? c / len : Vec3(0, 0, 1);

    if (!mesh.normals.empty()) {
        Vec3 n = mesh.normals[idx[0]] * b0 + mesh.normals[idx[1]] * b1 + mesh.normals[idx[2]] * b2;
        if (!inst.object_to_world.is_identity()) n = rs.world_to_object(hit.instance).normal_by_inverse(n);
        float nl = length(n);
        if (nl > 0.0f && std::isfinite(nl)) {
            n = n / nl;
            s.ns = dot(n, s.ng) < 0.0f ? -n : n;
        } else {
            s.ns = s.ng;
        }
    } else {
        s.ns = s.ng;
    }
    for (int set = 0; set < 2; ++set) {
        const std::vector<Vec2>& uv = set == 0 ? mesh.uv0 : mesh.uv1;
        if (uv.empty()) continue;
        s.attr.uv[set] = {b0 * uv[idx[0]].x + b1 * uv[idx[1]].x + b2 * uv[idx[2]].x,
                          b0 * uv[idx[0]].y + b1 * uv[idx[1]].y + b2 * uv[idx[2]].y};
    }
    if (!mesh.colors.empty()) {
        const Rgba& c0 = mesh.colors[idx[0]];
        const Rgba& c1 = mesh.colors[idx[1]];
        const Rgba& c2 = mesh.colors[idx[2]];
        s.attr.color = {b0 * c0.r + b1 * c1.r + b2 * c2.r, b0 * c0.g + b1 * c1.g + b2 * c2.g,
                        b0 * c0.b + b1 * c1.b + b2 * c2.b, b0 * c0.a + b1 * c1.a + b2 * c2.a};
    }
    return s;
}

Vec3 offset_ray_origin(const Vec3& p, const Vec3& p_error, const Vec3& ng, const Vec3& w) {
    float d = dot(abs(ng), p_error);
    Vec3 offset = ng * d;
    if (dot(w, ng) < 0.0f) offset = -offset;
    Vec3 po = p + offset;
    // Round away from p so the offset survives the addition's rounding.
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.0f) po[i] = next_float_up(po[i]);
        else if (offset[i] < 0.0f) po[i] = next_float_down(po[i]);
    }
    return po;
}

}  // namespace veach
