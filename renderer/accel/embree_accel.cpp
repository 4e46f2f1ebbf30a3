#include "accel/embree_accel.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/rng.h"
#include "materials/alpha.h"

namespace veach {

namespace {

// What an alpha filter needs to decide a hit: the mesh's attributes and its material.
struct AlphaGeometry {
    const Scene* scene;
    const Mesh* mesh;
    const Material* material;
};

// Embree calls this for every candidate hit on geometry with a MASK or BLEND material (and only
// there: opaque geometry has no filter and costs nothing). Rejecting a hit (valid = 0) lets the
// traversal continue past it. BLEND decides with a hash of the ray and the primitive, not a
// random stream: the same ray always makes the same decision, and since rays derive from the
// (seed, pixel, sample) stream, images stay independent of threads and scheduling.
void alpha_filter(const RTCFilterFunctionNArguments* args) {
    const auto* ag = static_cast<const AlphaGeometry*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) continue;
        unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
        float alpha = surface_alpha(*ag->scene, *ag->mesh, *ag->material, prim, u, v);
        float xi = 0.0f;
        if (ag->material->alpha_mode == AlphaMode::Blend) {
            uint64_t h = mix64(prim + 0x9e3779b97f4a7c15ull * (RTCHitN_instID(args->hit, args->N, i, 0) + 1ull));
            h = mix64(h ^ RTCHitN_geomID(args->hit, args->N, i));
            const float ray[6] = {RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                                  RTCRayN_org_z(args->ray, args->N, i), RTCRayN_dir_x(args->ray, args->N, i),
                                  RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i)};
            for (float f : ray) h = mix64(h ^ float_bits(f));
            xi = static_cast<float>(h >> 40) * 0x1p-24f;
        }
        if (!alpha_accepts(*ag->material, alpha, xi)) args->valid[i] = 0;
    }
}

thread_local uint64_t t_rejected_rays = 0;

// Embree's Ray::valid() (checked by assertions in Debian's build): |origin| and |direction|
// components within FLT_LARGE, t_max not NaN. NaN fails every comparison, so it is refused too.
bool traceable(const Vec3& o, const Vec3& d, float t_max) {
    const float m = k_max_ray_coordinate;
    const bool ok = std::fabs(o.x) <= m && std::fabs(o.y) <= m && std::fabs(o.z) <= m && std::fabs(d.x) <= m &&
                    std::fabs(d.y) <= m && std::fabs(d.z) <= m && !std::isnan(t_max);
    if (!ok) ++t_rejected_rays;
    return ok;
}

}  // namespace

uint64_t Accel::rejected_rays_on_this_thread() { return t_rejected_rays; }

struct Accel::Impl {
    const Scene& scene;
    RTCDevice device = nullptr;
    RTCScene top = nullptr;
    RTCScene static_scene = nullptr;                    // movable layout: the baked geometry, or null
    std::vector<RTCScene> mesh_scenes;                  // per mesh with a BVH of its own, else null
    std::vector<RTCGeometry> mesh_geometry;             // per mesh in a BVH of its own (retained)
    std::vector<Vec3*> mesh_vertices;                   // per deforming mesh: its Embree-owned vertices
    std::vector<std::vector<Vec3>> baked;               // per instance: world positions, or empty
    std::vector<uint32_t> geom_to_instance;             // top-level geometry id -> instance
    std::vector<RTCGeometry> instance_geometry;         // per instance referenced by an Embree instance
    std::vector<std::unique_ptr<AlphaGeometry>> alpha;  // filter data, stable addresses
    unsigned static_id = RTC_INVALID_GEOMETRY_ID;       // the static BVH's instance in the top level
    std::vector<uint32_t> static_to_instance;           // static BVH geometry id -> instance

    explicit Impl(const Scene& s) : scene(s) {}
    ~Impl() {
        for (RTCGeometry g : instance_geometry)
            if (g) rtcReleaseGeometry(g);
        for (RTCGeometry g : mesh_geometry)
            if (g) rtcReleaseGeometry(g);
        for (RTCScene sc : mesh_scenes)
            if (sc) rtcReleaseScene(sc);
        if (static_scene) rtcReleaseScene(static_scene);
        if (top) rtcReleaseScene(top);
        if (device) rtcReleaseDevice(device);
    }

    // A triangle geometry sharing our buffers. Embree reads vertices with 16-byte loads, so the
    // vertex array carries one padding element past the end.
    RTCGeometry make_triangles(const Vec3* positions, size_t vertex_count, const Mesh& mesh) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, positions, 0, sizeof(Vec3),
                                   vertex_count);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                                   3 * sizeof(uint32_t), mesh.triangle_count());
        install_alpha_filter(g, mesh);
        rtcCommitGeometry(g);
        return g;
    }

    // The BVH of mesh `m` in its own space, built once, for instances to reference. Embree needs
    // the padding element, so these meshes get their own copy of the vertices too; a deforming
    // mesh keeps a pointer to it (update() writes there) and asks for refitting.
    RTCScene mesh_scene(uint32_t m, bool deforming) {
        RTCScene& sub = mesh_scenes[m];
        if (sub) return sub;
        const Mesh& mesh = scene.meshes[m];
        sub = rtcNewScene(device);
        // Refitting is a per-geometry quality, which Embree honours in its two-level (LOW) mode.
        rtcSetSceneBuildQuality(sub, deforming ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_HIGH);
        RTCGeometry mg = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        if (deforming) rtcSetGeometryBuildQuality(mg, RTC_BUILD_QUALITY_REFIT);
        auto* vb = static_cast<Vec3*>(rtcSetNewGeometryBuffer(mg, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              sizeof(Vec3), mesh.positions.size()));
        std::copy(mesh.positions.begin(), mesh.positions.end(), vb);
        if (deforming) mesh_vertices[m] = vb;
        rtcSetSharedGeometryBuffer(mg, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                                   3 * sizeof(uint32_t), mesh.triangle_count());
        install_alpha_filter(mg, mesh);
        rtcCommitGeometry(mg);
        rtcAttachGeometry(sub, mg);
        mesh_geometry[m] = mg;  // our reference, kept for update()
        rtcCommitScene(sub);
        return sub;
    }

    // Alpha-tested materials get intersection and occlusion filters; everything else none.
    void install_alpha_filter(RTCGeometry g, const Mesh& mesh) {
        const Material& m = scene.material_of(mesh);
        if (!needs_alpha_test(m)) return;
        alpha.push_back(std::make_unique<AlphaGeometry>(AlphaGeometry{&scene, &mesh, &m}));
        rtcSetGeometryUserData(g, alpha.back().get());
        rtcSetGeometryIntersectFilterFunction(g, alpha_filter);
        rtcSetGeometryOccludedFilterFunction(g, alpha_filter);
    }

    void set_transform(RTCGeometry g, const Transform& t) {
        float xfm[12];  // RTC_FORMAT_FLOAT3X4_ROW_MAJOR
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) xfm[r * 4 + c] = t.m[r][c];
        rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
        rtcCommitGeometry(g);
    }

    unsigned attach(RTCGeometry g, uint32_t instance) {
        unsigned id = rtcAttachGeometry(top, g);
        if (geom_to_instance.size() <= id) geom_to_instance.resize(id + 1, 0);
        geom_to_instance[id] = instance;
        return id;
    }

    void check(const char* what) const {
        if (rtcGetDeviceError(device) != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what);
    }
};

namespace {
void embree_error(void*, RTCError code, const char* message) {
    (void)code;
    (void)message;  // reported through rtcGetDeviceError where it matters
}
}  // namespace

Accel::Accel(const Scene& scene) : m_impl(std::make_unique<Impl>(scene)) {
    Impl& d = *m_impl;
    d.device = rtcNewDevice("verbose=0");
    if (!d.device) throw std::runtime_error("Embree: cannot create a device");
    rtcSetDeviceErrorFunction(d.device, embree_error, nullptr);
    d.top = rtcNewScene(d.device);
    rtcSetSceneBuildQuality(d.top, RTC_BUILD_QUALITY_HIGH);

    std::vector<uint32_t> uses(scene.meshes.size(), 0);
    for (const Instance& inst : scene.instances) uses[inst.mesh]++;
    const std::vector<uint8_t> movable = movable_instances(scene);
    std::vector<uint8_t> deforming(scene.meshes.size(), 0);
    for (const DeformingMesh& dm : scene.animation.deforming) deforming[dm.mesh] = 1;
    const bool layered = std::find(movable.begin(), movable.end(), 1) != movable.end();
    if (layered) {
        d.static_scene = rtcNewScene(d.device);
        rtcSetSceneBuildQuality(d.static_scene, RTC_BUILD_QUALITY_HIGH);
    }
    d.mesh_scenes.assign(scene.meshes.size(), nullptr);
    d.mesh_geometry.assign(scene.meshes.size(), nullptr);
    d.mesh_vertices.assign(scene.meshes.size(), nullptr);
    d.instance_geometry.assign(scene.instances.size(), nullptr);
    d.baked.resize(scene.instances.size());
    // Top-level ids of the baked geometry in the static BVH: the instance it belongs to.
    std::vector<uint32_t> static_to_instance;

    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        const Mesh& mesh = scene.meshes[inst.mesh];
        if (mesh.triangle_count() == 0 || mesh.positions.empty()) continue;
        if (uses[inst.mesh] == 1 && !movable[i]) {
            std::vector<Vec3>& w = d.baked[i];
            w.resize(mesh.positions.size() + 1);
            for (size_t v = 0; v < mesh.positions.size(); ++v) w[v] = inst.object_to_world.point(mesh.positions[v]);
            RTCGeometry g = d.make_triangles(w.data(), mesh.positions.size(), mesh);
            if (layered) {
                unsigned id = rtcAttachGeometry(d.static_scene, g);
                if (static_to_instance.size() <= id) static_to_instance.resize(id + 1, 0);
                static_to_instance[id] = uint32_t(i);
            } else {
                d.attach(g, uint32_t(i));
            }
            rtcReleaseGeometry(g);
            continue;
        }
        RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, d.mesh_scene(inst.mesh, deforming[inst.mesh] != 0));
        d.set_transform(g, inst.object_to_world);
        d.attach(g, uint32_t(i));
        d.instance_geometry[i] = g;  // our reference, kept for update()
    }
    if (layered) {
        rtcCommitScene(d.static_scene);
        RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, d.static_scene);
        d.set_transform(g, Transform{});
        d.static_id = rtcAttachGeometry(d.top, g);
        rtcReleaseGeometry(g);
        d.static_to_instance = std::move(static_to_instance);
    }
    rtcCommitScene(d.top);
    d.check("building the acceleration structure failed");
}

bool Accel::update(const SceneChanges& changes) {
    Impl& d = *m_impl;
    const Scene& scene = d.scene;
    // Everything checked before anything is touched: a refusal leaves the accel as it was.
    for (uint32_t m : changes.deformed_meshes)
        if (m >= scene.meshes.size() || (scene.meshes[m].triangle_count() > 0 && !d.mesh_vertices[m])) return false;
    for (uint32_t i : changes.moved_instances) {
        if (i >= scene.instances.size()) return false;
        const Mesh& mesh = scene.meshes[scene.instances[i].mesh];
        if (mesh.triangle_count() > 0 && !mesh.positions.empty() && !d.instance_geometry[i]) return false;
    }
    bool top_changed = false;
    for (uint32_t m : changes.deformed_meshes) {
        const Mesh& mesh = scene.meshes[m];
        if (!d.mesh_vertices[m]) continue;
        std::copy(mesh.positions.begin(), mesh.positions.end(), d.mesh_vertices[m]);
        rtcUpdateGeometryBuffer(d.mesh_geometry[m], RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(d.mesh_geometry[m]);
        rtcCommitScene(d.mesh_scenes[m]);  // refits
        top_changed = true;
    }
    for (uint32_t i : changes.moved_instances) {
        if (!d.instance_geometry[i]) continue;
        d.set_transform(d.instance_geometry[i], scene.instances[i].object_to_world);
        top_changed = true;
    }
    if (top_changed) rtcCommitScene(d.top);
    d.check("updating the acceleration structure failed");
    return true;
}

Accel::~Accel() = default;

bool Accel::intersect(const Vec3& origin, const Vec3& dir, float t_max, RayHit* hit, float time) const {
    if (!traceable(origin, dir, t_max)) return false;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = origin.x;
    rh.ray.org_y = origin.y;
    rh.ray.org_z = origin.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = t_max;
    rh.ray.mask = 0xffffffffu;
    rh.ray.time = time;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_impl->top, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    unsigned top_id = rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? rh.hit.instID[0] : rh.hit.geomID;
    hit->t = rh.ray.tfar;
    hit->instance = top_id == m_impl->static_id ? m_impl->static_to_instance[rh.hit.geomID]
                                                : m_impl->geom_to_instance[top_id];
    hit->prim = rh.hit.primID;
    hit->u = rh.hit.u;
    hit->v = rh.hit.v;
    return true;
}

bool Accel::occluded(const Vec3& origin, const Vec3& dir, float t_max, float time) const {
    if (!traceable(origin, dir, t_max)) return true;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = origin.x;
    r.org_y = origin.y;
    r.org_z = origin.z;
    r.dir_x = dir.x;
    r.dir_y = dir.y;
    r.dir_z = dir.z;
    r.tnear = 0.0f;
    r.tfar = t_max;
    r.mask = 0xffffffffu;
    r.time = time;
    r.flags = 0;
    rtcOccluded1(m_impl->top, &ctx, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

void Accel::triangle_world(uint32_t instance, uint32_t prim, Vec3* p0, Vec3* p1, Vec3* p2) const {
    const Instance& inst = m_impl->scene.instances[instance];
    const Mesh& mesh = m_impl->scene.meshes[inst.mesh];
    const uint32_t* idx = &mesh.indices[static_cast<size_t>(prim) * 3];
    const std::vector<Vec3>& baked = m_impl->baked[instance];
    if (!baked.empty()) {
        *p0 = baked[idx[0]];
        *p1 = baked[idx[1]];
        *p2 = baked[idx[2]];
    } else {
        *p0 = inst.object_to_world.point(mesh.positions[idx[0]]);
        *p1 = inst.object_to_world.point(mesh.positions[idx[1]]);
        *p2 = inst.object_to_world.point(mesh.positions[idx[2]]);
    }
}

}  // namespace veach
