#include "scene/scene_repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

namespace veach {

namespace {

// |e1 x e2| = |e1| |e2| sin(angle between them). Below this sine the corners are collinear to
// float precision: the cross product is rounding noise, so neither the normal nor the area means
// anything. The test is relative, so it does not depend on the scene's scale.
constexpr double k_collinear_sine = 1e-6;

// Normals within this of unit length (squared) are left as the file gave them: exporters write
// 8-bit-normalised or rounded normals and renormalising them changes nothing visible.
constexpr float k_unit_tolerance = 1e-4f;

bool finite2(const Vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }

struct DVec3 {
    double x, y, z;
};
DVec3 to_double(const Vec3& v) { return {v.x, v.y, v.z}; }
DVec3 sub(const DVec3& a, const DVec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
DVec3 cross(const DVec3& a, const DVec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double norm(const DVec3& a) { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }

// An order-independent 64-bit key of a triangle's three corner positions: coincident faces with
// any winding get the same key. Equal keys are confirmed by comparing the positions exactly.
uint64_t position_hash(const Vec3& p) {
    uint32_t b[3];
    std::memcpy(b, &p, sizeof(b));
    uint64_t h = 1469598103934665603ull;  // FNV-1a over the 12 bytes
    for (uint32_t w : b) {
        for (int i = 0; i < 4; ++i) {
            h ^= (w >> (8 * i)) & 0xffu;
            h *= 1099511628211ull;
        }
    }
    return h;
}

std::array<Vec3, 3> sorted_corners(const Mesh& mesh, size_t t) {
    std::array<Vec3, 3> c = {mesh.positions[mesh.indices[3 * t]], mesh.positions[mesh.indices[3 * t + 1]],
                             mesh.positions[mesh.indices[3 * t + 2]]};
    std::sort(c.begin(), c.end(), [](const Vec3& a, const Vec3& b) {
        if (a.x != b.x) return a.x < b.x;
        if (a.y != b.y) return a.y < b.y;
        return a.z < b.z;
    });
    return c;
}

bool same_position(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// Drops triangles that cannot be rendered; returns the kept indices in place.
void drop_bad_triangles(Mesh& mesh, RepairCounts& counts) {
    const size_t n = mesh.positions.size();
    std::vector<uint8_t> finite(n);
    for (size_t i = 0; i < n; ++i) finite[i] = is_finite(mesh.positions[i]) ? 1 : 0;
    size_t kept = 0;
    const size_t tris = mesh.indices.size() / 3;
    for (size_t t = 0; t < tris; ++t) {
        uint32_t i0 = mesh.indices[3 * t], i1 = mesh.indices[3 * t + 1], i2 = mesh.indices[3 * t + 2];
        if (i0 >= n || i1 >= n || i2 >= n) {
            ++counts.invalid_indices;
            continue;
        }
        if (!finite[i0] || !finite[i1] || !finite[i2]) {
            ++counts.nonfinite_triangles;
            continue;
        }
        // In double: the float corners are exact there, so the sine test measures the triangle,
        // not the rounding of the test itself.
        DVec3 p0 = to_double(mesh.positions[i0]);
        DVec3 e1 = sub(to_double(mesh.positions[i1]), p0), e2 = sub(to_double(mesh.positions[i2]), p0);
        double area2 = norm(cross(e1, e2));
        if (i0 == i1 || i1 == i2 || i0 == i2 || !(area2 > k_collinear_sine * norm(e1) * norm(e2))) {
            ++counts.degenerate_triangles;
            continue;
        }
        mesh.indices[3 * kept] = i0;
        mesh.indices[3 * kept + 1] = i1;
        mesh.indices[3 * kept + 2] = i2;
        ++kept;
    }
    mesh.indices.resize(3 * kept);
}

// Drops every later copy of a face whose three corner positions equal an earlier face's. Sorting
// 16-byte (key, triangle) pairs keeps the extra memory small for meshes of millions of faces.
void drop_duplicate_triangles(Mesh& mesh, RepairCounts& counts) {
    const size_t tris = mesh.triangle_count();
    if (tris < 2) return;
    std::vector<std::pair<uint64_t, uint32_t>> keys(tris);
    for (size_t t = 0; t < tris; ++t) {
        uint64_t h[3] = {position_hash(mesh.positions[mesh.indices[3 * t]]),
                         position_hash(mesh.positions[mesh.indices[3 * t + 1]]),
                         position_hash(mesh.positions[mesh.indices[3 * t + 2]])};
        std::sort(h, h + 3);
        uint64_t key = h[0] * 0x9e3779b97f4a7c15ull ^ (h[1] + 0x632be59bd9b4e019ull + (h[0] << 6));
        key = key * 0xbf58476d1ce4e5b9ull ^ (h[2] + (key >> 29));
        keys[t] = {key, static_cast<uint32_t>(t)};
    }
    std::sort(keys.begin(), keys.end());  // ties by triangle index: the first copy is kept
    std::vector<uint8_t> drop(tris, 0);
    bool any = false;
    for (size_t a = 0; a < tris;) {
        size_t b = a + 1;
        while (b < tris && keys[b].first == keys[a].first) ++b;
        for (size_t i = a; i < b; ++i) {
            if (drop[keys[i].second]) continue;
            std::array<Vec3, 3> ci = sorted_corners(mesh, keys[i].second);
            for (size_t j = i + 1; j < b; ++j) {
                if (drop[keys[j].second]) continue;
                std::array<Vec3, 3> cj = sorted_corners(mesh, keys[j].second);
                if (same_position(ci[0], cj[0]) && same_position(ci[1], cj[1]) && same_position(ci[2], cj[2])) {
                    drop[keys[j].second] = 1;
                    any = true;
                }
            }
        }
        a = b;
    }
    if (!any) return;
    size_t kept = 0;
    for (size_t t = 0; t < tris; ++t) {
        if (drop[t]) {
            ++counts.duplicate_triangles;
            continue;
        }
        for (int k = 0; k < 3; ++k) mesh.indices[3 * kept + k] = mesh.indices[3 * t + k];
        ++kept;
    }
    mesh.indices.resize(3 * kept);
}

void repair_normals(Mesh& mesh, RepairCounts& counts) {
    if (mesh.normals.empty()) return;
    std::vector<uint32_t> bad;
    for (size_t i = 0; i < mesh.normals.size(); ++i) {
        Vec3& n = mesh.normals[i];
        float len2 = length_squared(n);
        if (!is_finite(n) || !std::isfinite(len2) || !(len2 > 0.0f)) {
            bad.push_back(static_cast<uint32_t>(i));
        } else if (std::fabs(len2 - 1.0f) > k_unit_tolerance) {
            // Scale first so that tiny or huge finite normals do not underflow or overflow.
            Vec3 s = n / max_component(abs(n));
            n = s / length(s);
            ++counts.normals_normalized;
        }
    }
    if (bad.empty()) return;
    // The area-weighted average of the faces around the vertex: the cross product's length is
    // twice the area, so summing unnormalised face normals weights them by area.
    // Summed in double: the corners' products neither overflow nor underflow there.
    std::vector<DVec3> sum(mesh.normals.size(), DVec3{0, 0, 0});
    std::vector<uint8_t> is_bad(mesh.normals.size(), 0);
    for (uint32_t i : bad) is_bad[i] = 1;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const uint32_t* idx = &mesh.indices[3 * t];
        if (!is_bad[idx[0]] && !is_bad[idx[1]] && !is_bad[idx[2]]) continue;
        DVec3 p0 = to_double(mesh.positions[idx[0]]);
        DVec3 c = cross(sub(to_double(mesh.positions[idx[1]]), p0), sub(to_double(mesh.positions[idx[2]]), p0));
        for (int k = 0; k < 3; ++k) {
            if (!is_bad[idx[k]]) continue;
            DVec3& a = sum[idx[k]];
            a = {a.x + c.x, a.y + c.y, a.z + c.z};
        }
    }
    for (uint32_t i : bad) {
        double len = norm(sum[i]);
        // A vertex no face uses keeps a zero normal: it is never interpolated alone.
        mesh.normals[i] =
            len > 0.0 ? Vec3(float(sum[i].x / len), float(sum[i].y / len), float(sum[i].z / len)) : Vec3(0, 0, 0);
        ++counts.normals_replaced;
    }
}

void repair_attributes(Mesh& mesh, RepairCounts& counts) {
    for (std::vector<Vec2>* uv : {&mesh.uv0, &mesh.uv1}) {
        for (Vec2& t : *uv) {
            if (finite2(t)) continue;
            t = Vec2{0.0f, 0.0f};
            ++counts.uvs_replaced;
        }
    }
    for (Rgba& c : mesh.colors) {
        if (std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && std::isfinite(c.a)) continue;
        c = Rgba{1, 1, 1, 1};
        ++counts.colors_replaced;
    }
}

bool light_is_finite(const PunctualLight& l) {
    return is_finite(l.position) && is_finite(l.direction) && l.intensity.is_finite() && std::isfinite(l.cos_outer) &&
           std::isfinite(l.cos_inner) && std::isfinite(l.blend) && std::isfinite(l.radius) && std::isfinite(l.angle) &&
           is_finite(l.axis_u) && is_finite(l.axis_v) && l.radiance.is_finite();
}

std::string summary(const RepairCounts& c) {
    std::string s;
    auto add = [&](uint64_t n, const char* what) {
        if (n == 0) return;
        s += (s.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    };
    add(c.invalid_indices, "triangles with an index out of range dropped");
    add(c.nonfinite_triangles, "triangles with non-finite corners dropped");
    add(c.degenerate_triangles, "degenerate (zero-area, collinear or repeated-corner) triangles dropped");
    add(c.duplicate_triangles, "duplicate faces dropped");
    add(c.normals_replaced, "invalid normals replaced by the face normals' average");
    add(c.normals_normalized, "non-unit normals normalised");
    add(c.uvs_replaced, "non-finite texture coordinates set to 0");
    add(c.colors_replaced, "non-finite vertex colours set to 1");
    add(c.lights_dropped, "lights with non-finite parameters dropped");
    return "repaired geometry: " + s;
}

}  // namespace

RepairCounts repair_scene(Scene& scene) {
    RepairCounts counts;
    for (Mesh& mesh : scene.meshes) {
        drop_bad_triangles(mesh, counts);
        drop_duplicate_triangles(mesh, counts);
        repair_normals(mesh, counts);
        repair_attributes(mesh, counts);
    }
    size_t kept = 0;
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        if (!light_is_finite(scene.lights[i])) {
            ++counts.lights_dropped;
            continue;
        }
        if (kept != i) scene.lights[kept] = std::move(scene.lights[i]);
        ++kept;
    }
    scene.lights.resize(kept);

    RepairCounts& total = scene.repaired;
    total.nonfinite_triangles += counts.nonfinite_triangles;
    total.invalid_indices += counts.invalid_indices;
    total.degenerate_triangles += counts.degenerate_triangles;
    total.duplicate_triangles += counts.duplicate_triangles;
    total.normals_replaced += counts.normals_replaced;
    total.normals_normalized += counts.normals_normalized;
    total.uvs_replaced += counts.uvs_replaced;
    total.colors_replaced += counts.colors_replaced;
    total.lights_dropped += counts.lights_dropped;
    if (counts.total() > 0) scene.warnings.push_back(summary(counts));
    return counts;
}

Vec3 rebase_scene(Scene& scene) {
    // The bounds of the triangles' corners only: unreferenced vertices may hold anything.
    return rebase_scene(scene, scene.bounds());
}

Vec3 rebase_scene(Scene& scene, const Bounds3& b) {
    if (b.empty() || !is_finite(b.lo) || !is_finite(b.hi)) return Vec3(0, 0, 0);
    // In double: the float centre of a box near 1e5 would already be rounded.
    const double centre[3] = {0.5 * (double(b.lo.x) + b.hi.x), 0.5 * (double(b.lo.y) + b.hi.y),
                              0.5 * (double(b.lo.z) + b.hi.z)};
    double size = norm(sub(to_double(b.hi), to_double(b.lo)));
    if (!(std::max({std::fabs(centre[0]), std::fabs(centre[1]), std::fabs(centre[2])}) > size)) return Vec3(0, 0, 0);
    const Vec3 offset{float(centre[0]), float(centre[1]), float(centre[2])};
    auto shift = [&](Transform& t) {
        for (int r = 0; r < 3; ++r) t.m[r][3] = float(double(t.m[r][3]) - double(offset[r]));
    };
    for (Instance& inst : scene.instances) shift(inst.object_to_world);
    for (Camera& cam : scene.cameras) shift(cam.camera_to_world);
    for (auto& steps : scene.motion.camera_to_world)
        for (Transform& t : steps) shift(t);
    for (auto& steps : scene.motion.instance_to_world)
        for (Transform& t : steps) shift(t);
    for (PunctualLight& l : scene.lights)
        for (int r = 0; r < 3; ++r) l.position[r] = float(double(l.position[r]) - double(offset[r]));
    return offset;
}

bool light_unlit_scene(Scene& scene) {
    if (scene.environment.enabled || !scene.lights.empty()) return false;
    for (const Instance& inst : scene.instances) {
        const Mesh& mesh = scene.meshes[inst.mesh];
        if (mesh.triangle_count() > 0 && scene.material_of(mesh).is_emissive()) return false;
    }
    scene.environment = Environment{};
    scene.environment.enabled = true;
    scene.environment.color = Rgb(1.0f);
    scene.features.environment = true;
    scene.warnings.push_back("the scene has no lights; lighting it with a uniform white environment (radiance 1)");
    return true;
}

}  // namespace veach
