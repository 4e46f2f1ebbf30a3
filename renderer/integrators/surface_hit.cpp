#include "integrators/surface_hit.h"

#include "materials/gltf_material.h"

namespace veach {

namespace {

// Where a hit's instance and vertices stand at the hit's shutter time: the instance's transform
// and its inverse (its own, or the moving one Embree traced against), and for a deforming mesh
// the two vertex steps around the time with the fraction between them (Accel's interpolation).
struct HitPlacement {
    const Transform* object_to_world = nullptr;
    const Transform* world_to_object = nullptr;
    Transform moving_to_world, moving_to_object;
    const MeshMotion* steps = nullptr;  // null: the mesh's own vertices
    size_t k = 0;
    float f = 0;

    HitPlacement(const RenderScene& rs, const RayHit& hit) {
        const Instance& inst = rs.scene().instances[hit.instance];
        if (rs.accel().moving_transform(hit.instance, hit.time, &moving_to_world)) {
            moving_to_object = inverse(moving_to_world);
            object_to_world = &moving_to_world;
            world_to_object = &moving_to_object;
        } else {
            object_to_world = &inst.object_to_world;
            world_to_object = &rs.world_to_object(hit.instance);
        }
        if (rs.accel().mesh_deforms(inst.mesh)) {
            steps = &rs.scene().motion.meshes[inst.mesh];
            int step;
            motion_segment(hit.time, rs.scene().motion.steps, &step, &f);
            k = size_t(step);
        }
    }
    // A per-vertex attribute (normals, tangents) at the barycentrics, at the hit's time. `which`
    // picks the same array of a motion step.
    Vec3 attribute(const std::vector<Vec3>& still, std::vector<std::vector<Vec3>> MeshMotion::*which,
                   const uint32_t* idx, float b0, float b1, float b2) const {
        if (!steps) return interpolate_vertices(still, idx, b0, b1, b2);
        const auto& a = (steps->*which)[k];
        const auto& b = (steps->*which)[k + 1];
        return interpolate_vertices(a, idx, b0, b1, b2) * (1.0f - f) + interpolate_vertices(b, idx, b0, b1, b2) * f;
    }
};

// Bound on the relative error of n floating-point operations (pbrt's gamma(n)), widened for
// the instance transform applied to the vertices before interpolation.
constexpr float k_position_error_scale = 32.0f * 0x1p-24f;
}  // namespace

// The shading normal from a tangent-space normal map (glTF 2.0 section 3.9.3): the texel
// (r, g, b) decodes to n_ts = normalize((2r - 1) scale, (2g - 1) scale, 2b - 1) in the frame
// (tangent, bitangent = cross(normal, tangent) w, normal). `ns` and `ng` are on the same side;
// the vertex normal before that flip is recovered from them. The result is kept at least slightly
// above the geometric surface on ng's side: a normal map must not turn a surface inside out.
static Vec3 apply_normal_map(const RenderScene& rs, const TextureRef& ref, float scale, const Mesh& mesh,
                      const HitPlacement& at, const uint32_t* idx, float b0, float b1, float b2,
                      const SurfaceAttributes& attr, const Vec3& ng, const Vec3& ns) {
    if (static_cast<size_t>(ref.texture) >= rs.scene().textures.size()) return ns;
    Vec3 t = at.attribute(mesh.tangents, &MeshMotion::tangents, idx, b0, b1, b2);
    float w = mesh.tangent_signs[idx[0]];
    const Transform& o2w = *at.object_to_world;
    if (!o2w.is_identity()) {
        t = o2w.vector(t);
        if (o2w.determinant() < 0.0f) w = -w;  // a mirroring placement flips handedness
    }
    // The vertex normal's own orientation (before SurfaceHit flipped it to ng's side) decides the
    // bitangent's direction.
    Vec3 n = ns;
    if (!mesh.normals.empty()) {
        Vec3 nv = at.attribute(mesh.normals, &MeshMotion::normals, idx, b0, b1, b2);
        if (!o2w.is_identity()) nv = at.world_to_object->normal_by_inverse(nv);
        if (dot(nv, n) < 0.0f) n = -n;
    }
    t = t - n * dot(n, t);
    float lt = length(t);
    if (!(lt > 0.0f) || !std::isfinite(lt)) return ns;
    t = t / lt;
    Vec3 b = cross(n, t) * w;
    Rgba texel = lookup_texture(ref, rs.scene(), attr);
    float x = (2.0f * texel.r - 1.0f) * scale, y = (2.0f * texel.g - 1.0f) * scale;
    float z = 2.0f * texel.b - 1.0f;
    Vec3 m = t * x + b * y + n * z;
    float lm = length(m);
    if (!(lm > 0.0f) || !std::isfinite(lm)) return ns;
    m = m / lm;
    if (dot(m, ng) < 0.0f && dot(n, ng) < 0.0f) m = -m;  // back to ng's side, as ns was
    // Bend toward ng, keeping the azimuth, so the normal stays above the geometric surface by a
    // small margin (cos >= k_min_cos). Independent of the viewing direction, so the BSDF's frame
    // stays a property of the surface point (reciprocity; see SurfaceBsdf).
    constexpr float k_min_cos = 0.02f;
    float c = dot(m, ng);
    if (c < k_min_cos) {
        Vec3 tangential = m - ng * c;
        float l = length(tangential);
        m = l > 0.0f ? tangential * (std::sqrt(1.0f - k_min_cos * k_min_cos) / l) + ng * k_min_cos : ng;
    }
    return m;
}

namespace {

// The ray cone's footprint in texture space (after Akenine-Moller et al. 2019, section 20.3.4): a
// cone of width w meeting the surface at angle theta to its normal covers an ellipse w wide across
// and w / cos(theta) long, and the triangle's UV area over its world area turns world lengths into
// UV lengths (the square root of the ratio). An isotropic lookup cannot match both axes; we give
// it the short one, w, as GPUs' anisotropic filtering picks its level from the minor axis (then
// adds taps along the major one, which we leave to the pixel's many samples). The paper's choice,
// the long axis w / cos, blurs grazing surfaces across as much as along: in a path tracer, which
// averages many samples per pixel, leftover aliasing is averaged away while blur is a bias no
// sample count removes. Measured on the grazing plane of tests/render/test_textured_mipmap with
// 8-texel checks (per-pixel RMS difference from supersampled full resolution, noise of 0.022
// included; per-sample variance 0.109 at full resolution): w gives RMS 0.023 (no bias above the
// noise), variance 0.069; w / sqrt(cos) 0.047 and 0.033; w / cos 0.104 and 0.014. In mean
// squared error (bias^2 + variance / spp) w / sqrt(cos) falls behind full resolution past ~45
// spp and w / cos past ~9; w was ahead at every count we could resolve.
void set_uv_footprint(const Mesh& mesh, const uint32_t* idx, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                      float width, SurfaceAttributes* attr) {
    float world_area = length(cross(p1 - p0, p2 - p0));  // twice the area, as uv_area below
    if (!(world_area > 0.0f)) return;
    for (int set = 0; set < 2; ++set) {
        const std::vector<Vec2>& uv = set == 0 ? mesh.uv0 : mesh.uv1;
        if (uv.empty()) continue;
        Vec2 a = uv[idx[0]], b = uv[idx[1]], c = uv[idx[2]];
        float uv_area = std::fabs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
        float f = width * std::sqrt(uv_area / world_area);
        attr->uv_footprint[set] = std::isfinite(f) ? f : 0.0f;
    }
}

}  // namespace

SurfaceHit make_surface_hit(const RenderScene& rs, const RayHit& hit, float footprint_width) {
    const Scene& scene = rs.scene();
    SurfaceHit s;
    s.instance = hit.instance;
    s.prim = hit.prim;
    const Instance& inst = scene.instances[hit.instance];
    const Mesh& mesh = scene.meshes[inst.mesh];
    s.material = &scene.material_of(mesh);
    s.thin_walled = rs.thin_walled(inst.mesh);
    const uint32_t* idx = &mesh.indices[static_cast<size_t>(hit.prim) * 3];
    float b1 = hit.u, b2 = hit.v, b0 = 1.0f - b1 - b2;
    s.b1 = b1;
    s.b2 = b2;

    const HitPlacement at(rs, hit);
    Vec3 p0, p1, p2;
    rs.accel().triangle_world(hit.instance, hit.prim, &p0, &p1, &p2, hit.time);
    s.p = barycentric(p0, p1, p2, b0, b1, b2);
    s.p_error = (abs(p0 * b0) + abs(p1 * b1) + abs(p2 * b2)) * k_position_error_scale;

    Vec3 c = cross(p1 - p0, p2 - p0);
    float len = length(c);
    s.ng = len > 0.0f ? c / len : Vec3(0, 0, 1);

    if (!mesh.normals.empty()) {
        Vec3 n = at.attribute(mesh.normals, &MeshMotion::normals, idx, b0, b1, b2);
        if (!at.object_to_world->is_identity()) n = at.world_to_object->normal_by_inverse(n);
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
    interpolate_uvs(mesh, idx, b0, b1, b2, &s.attr);
    if (footprint_width > 0.0f) set_uv_footprint(mesh, idx, p0, p1, p2, footprint_width, &s.attr);
    bool has_tangents = mesh.tangents.size() == mesh.positions.size();
    const Material& mat = *s.material;
    const Vec3 ns_vertex = s.ns;
    if (mat.normal_texture.valid() && has_tangents) {
        s.ns = apply_normal_map(rs, mat.normal_texture, mat.normal_scale, mesh, at, idx, b0, b1, b2, s.attr, s.ng,
                                s.ns);
        s.ns_vertex = ns_vertex;
        s.normal_mapped = true;
    }
    // KHR_materials_clearcoat: the coat has its own normal map, and without one it is *not*
    // normal-mapped like the base (the extension's wording): the vertex normal. Zero when the
    // coat's normal is the base's, so the BSDF keeps its untilted path.
    if (mat.clearcoat > 0.0f) {
        if (mat.clearcoat_normal_texture.valid() && has_tangents)
            s.ns_coat = apply_normal_map(rs, mat.clearcoat_normal_texture, mat.clearcoat_normal_scale, mesh, at, idx,
                                         b0, b1, b2, s.attr, s.ng, ns_vertex);
        else if (mat.normal_texture.valid())
            s.ns_coat = ns_vertex;
    }
    if (!mesh.colors.empty()) s.attr.color = interpolate_vertices(mesh.colors, idx, b0, b1, b2);
    return s;
}

Vec3 offset_ray_origin(const Vec3& p, const Vec3& p_error, const Vec3& ng, const Vec3& w) {
    float d = dot(abs(ng), p_error);
    Vec3 offset = ng * d;
    if (dot(w, ng) < 0.0f) offset = -offset;
    Vec3 po = p + offset;
    // Round away from p so the offset survives the addition's rounding.
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.0f)
            po[i] = next_float_up(po[i]);
        else if (offset[i] < 0.0f)
            po[i] = next_float_down(po[i]);
    }
    return po;
}

}  // namespace veach
