#include "accel/embree_accel.h"

#include <embree3/rtcore.h>

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
    std::vector<RTCScene> mesh_scenes;                  // per mesh placed several times, else null
    std::vector<std::vector<Vec3>> baked;               // per instance: world positions, or empty
    std::vector<uint32_t> geom_to_instance;             // top-level geometry id -> instance
    std::vector<std::unique_ptr<AlphaGeometry>> alpha;  // filter data, stable addresses

    explicit Impl(const Scene& s) : scene(s) {}
    ~Impl() {
        for (RTCScene sc : mesh_scenes)
            if (sc) rtcReleaseScene(sc);
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

    // Alpha-tested materials get intersection and occlusion filters; everything else none.
    void install_alpha_filter(RTCGeometry g, const Mesh& mesh) {
        const Material& m = scene.material_of(mesh);
        if (!needs_alpha_test(m)) return;
        alpha.push_back(std::make_unique<AlphaGeometry>(AlphaGeometry{&scene, &mesh, &m}));
        rtcSetGeometryUserData(g, alpha.back().get());
        rtcSetGeometryIntersectFilterFunction(g, alpha_filter);
        rtcSetGeometryOccludedFilterFunction(g, alpha_filter);
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
    d.mesh_scenes.assign(scene.meshes.size(), nullptr);
    d.baked.resize(scene.instances.size());

    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        const Mesh& mesh = scene.meshes[inst.mesh];
        if (mesh.triangle_count() == 0 || mesh.positions.empty()) continue;
        RTCGeometry g;
        if (uses[inst.mesh] == 1) {
            std::vector<Vec3>& w = d.baked[i];
            w.resize(mesh.positions.size() + 1);
            for (size_t v = 0; v < mesh.positions.size(); ++v) w[v] = inst.object_to_world.point(mesh.positions[v]);
            g = d.make_triangles(w.data(), mesh.positions.size(), mesh);
        } else {
            RTCScene& sub = d.mesh_scenes[inst.mesh];
            if (!sub) {
                sub = rtcNewScene(d.device);
                rtcSetSceneBuildQuality(sub, RTC_BUILD_QUALITY_HIGH);
                // Embree needs the padding element, so instanced meshes get their own copy too.
                RTCGeometry mg = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
                auto* vb = static_cast<Vec3*>(rtcSetNewGeometryBuffer(mg, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                      sizeof(Vec3), mesh.positions.size()));
                std::copy(mesh.positions.begin(), mesh.positions.end(), vb);
                rtcSetSharedGeometryBuffer(mg, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                                           3 * sizeof(uint32_t), mesh.triangle_count());
                d.install_alpha_filter(mg, mesh);
                rtcCommitGeometry(mg);
                rtcAttachGeometry(sub, mg);
                rtcReleaseGeometry(mg);
                rtcCommitScene(sub);
            }
            g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(g, sub);
            float xfm[12];  // RTC_FORMAT_FLOAT3X4_ROW_MAJOR
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c) xfm[r * 4 + c] = inst.object_to_world.m[r][c];
            rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
            rtcCommitGeometry(g);
        }
        unsigned id = rtcAttachGeometry(d.top, g);
        rtcReleaseGeometry(g);
        if (d.geom_to_instance.size() <= id) d.geom_to_instance.resize(id + 1, 0);
        d.geom_to_instance[id] = static_cast<uint32_t>(i);
    }
    rtcCommitScene(d.top);
    if (rtcGetDeviceError(d.device) != RTC_ERROR_NONE)
        throw std::runtime_error("Embree: building the acceleration structure failed");
}

Accel::~Accel() = default;

bool Accel::intersect(const Vec3& origin, const Vec3& dir, float t_max, RayHit* hit) const {
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
    rh.ray.time = 0.0f;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_impl->top, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    unsigned top_id = rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? rh.hit.instID[0] : rh.hit.geomID;
    hit->t = rh.ray.tfar;
    hit->instance = m_impl->geom_to_instance[top_id];
    hit->prim = rh.hit.primID;
    hit->u = rh.hit.u;
    hit->v = rh.hit.v;
    return true;
}

bool Accel::occluded(const Vec3& origin, const Vec3& dir, float t_max) const {
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
    r.time = 0.0f;
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
