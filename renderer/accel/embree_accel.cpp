#include "accel/embree_accel.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/rng.h"
#include "scene/scene_motion.h"
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

// M's 3x3 part as Q U (Gram-Schmidt on its columns: Q a rotation, U upper triangular, a mirroring
// M's sign in U's last diagonal entry) and its translation: Embree's T R S with no shift. False
// for a singular M, which keeps linear interpolation of its matrices.
bool decompose(const Transform& m, RTCQuaternionDecomposition* qd) {
    double c[3][3], q[3][3], u[3][3] = {};
    for (int j = 0; j < 3; ++j)
        for (int r = 0; r < 3; ++r) c[j][r] = m.m[r][j];
    auto dotd = [](const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    for (int j = 0; j < 3; ++j) {
        double v[3] = {c[j][0], c[j][1], c[j][2]};
        for (int i = 0; i < j; ++i) {
            u[i][j] = dotd(q[i], c[j]);
            for (int r = 0; r < 3; ++r) v[r] -= u[i][j] * q[i][r];
        }
        u[j][j] = std::sqrt(dotd(v, v));
        if (!(u[j][j] > 1e-30) || !std::isfinite(u[j][j])) return false;
        for (int r = 0; r < 3; ++r) q[j][r] = v[r] / u[j][j];
    }
    const double cr[3] = {q[0][1] * q[1][2] - q[0][2] * q[1][1], q[0][2] * q[1][0] - q[0][0] * q[1][2],
                          q[0][0] * q[1][1] - q[0][1] * q[1][0]};
    if (dotd(cr, q[2]) < 0) {
        for (int r = 0; r < 3; ++r) q[2][r] = -q[2][r];
        u[2][2] = -u[2][2];
    }
    Transform rot;
    for (int r = 0; r < 3; ++r)
        for (int j = 0; j < 3; ++j) rot.m[r][j] = float(q[j][r]);
    const std::array<float, 4> quat = quaternion_of_rotation(rot);
    rtcInitQuaternionDecomposition(qd);
    rtcQuaternionDecompositionSetScale(qd, float(u[0][0]), float(u[1][1]), float(u[2][2]));
    rtcQuaternionDecompositionSetSkew(qd, float(u[0][1]), float(u[0][2]), float(u[1][2]));
    rtcQuaternionDecompositionSetQuaternion(qd, quat[3], quat[0], quat[1], quat[2]);
    rtcQuaternionDecompositionSetTranslation(qd, m.m[0][3], m.m[1][3], m.m[2][3]);
    return true;
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
    std::vector<int> instance_steps;                    // per instance: Embree time steps (1: still)
    std::vector<int> mesh_steps;                        // per mesh: its vertices' time steps (1: still)

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
        sub = rtcNewScene(device);
        // Refitting is a per-geometry quality, which Embree honours in its two-level (LOW) mode.
        rtcSetSceneBuildQuality(sub, deforming ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_HIGH);
        RTCGeometry mg = mesh_geometry_of(m, deforming);
        rtcAttachGeometry(sub, mg);
        mesh_geometry[m] = mg;  // our reference, kept for update()
        rtcCommitScene(sub);
        return sub;
    }

    // Mesh m's triangles in its own space with Embree-owned vertices: one buffer per time step
    // when it deforms during the shutter (scene.motion), else the mesh's positions.
    RTCGeometry mesh_geometry_of(uint32_t m, bool deforming) {
        const Mesh& mesh = scene.meshes[m];
        RTCGeometry mg = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        if (deforming) rtcSetGeometryBuildQuality(mg, RTC_BUILD_QUALITY_REFIT);
        const bool steps = deforming && scene.motion.mesh_deforms(m);
        mesh_steps[m] = steps ? scene.motion.steps : 1;
        if (steps) rtcSetGeometryTimeStepCount(mg, unsigned(mesh_steps[m]));
        for (int k = 0; k < mesh_steps[m]; ++k) {
            const std::vector<Vec3>& p = steps ? scene.motion.meshes[m].positions[size_t(k)] : mesh.positions;
            auto* vb = static_cast<Vec3*>(rtcSetNewGeometryBuffer(mg, RTC_BUFFER_TYPE_VERTEX, unsigned(k),
                                                                  RTC_FORMAT_FLOAT3, sizeof(Vec3), p.size()));
            std::copy(p.begin(), p.end(), vb);
            if (deforming && k == 0) mesh_vertices[m] = vb;
        }
        rtcSetSharedGeometryBuffer(mg, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                                   3 * sizeof(uint32_t), mesh.triangle_count());
        install_alpha_filter(mg, mesh);
        rtcCommitGeometry(mg);
        return mg;
    }

    // A deforming mesh's new vertices (every time step): copied into its buffers, or, when its
    // number of time steps changed, a new geometry in place of the old one. Its BVH is refitted
    // (rebuilt after a new geometry) by the commit.
    void update_mesh(uint32_t m) {
        const int want = scene.motion.mesh_deforms(m) ? scene.motion.steps : 1;
        if (want != mesh_steps[m]) {
            rtcDetachGeometry(mesh_scenes[m], 0);
            rtcReleaseGeometry(mesh_geometry[m]);
            mesh_geometry[m] = mesh_geometry_of(m, true);
            rtcAttachGeometryByID(mesh_scenes[m], mesh_geometry[m], 0);
        } else {
            for (int k = 0; k < mesh_steps[m]; ++k) {
                const std::vector<Vec3>& p =
                    want > 1 ? scene.motion.meshes[m].positions[size_t(k)] : scene.meshes[m].positions;
                auto* vb = static_cast<Vec3*>(rtcGetGeometryBufferData(mesh_geometry[m], RTC_BUFFER_TYPE_VERTEX, unsigned(k)));
                std::copy(p.begin(), p.end(), vb);
                rtcUpdateGeometryBuffer(mesh_geometry[m], RTC_BUFFER_TYPE_VERTEX, unsigned(k));
            }
            rtcCommitGeometry(mesh_geometry[m]);
        }
        rtcCommitScene(mesh_scenes[m]);
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

    // Instance i's transform: its time steps when it moves during the shutter (scene.motion), as
    // quaternion decompositions so that Embree slerps the rotation (linear matrices when one is
    // singular), else the one transform.
    void set_instance_transform(uint32_t i) {
        RTCGeometry g = instance_geometry[i];
        const bool moves = scene.motion.instance_moves(i);
        const std::vector<Transform>* steps = moves ? &scene.motion.instance_to_world[i] : nullptr;
        if (!steps) {
            if (instance_steps[i] != 1) rtcSetGeometryTimeStepCount(g, 1);
            instance_steps[i] = 1;
            set_transform(g, scene.instances[i].object_to_world);
            return;
        }
        std::vector<RTCQuaternionDecomposition> qd(steps->size());
        bool quaternions = true;
        for (size_t k = 0; k < steps->size() && quaternions; ++k) quaternions = decompose((*steps)[k], &qd[k]);
        // Each rotation on the same side as the one before: Embree slerps the shorter arc then.
        for (size_t k = 1; quaternions && k < qd.size(); ++k) {
            const float d = qd[k].quaternion_r * qd[k - 1].quaternion_r + qd[k].quaternion_i * qd[k - 1].quaternion_i +
                            qd[k].quaternion_j * qd[k - 1].quaternion_j + qd[k].quaternion_k * qd[k - 1].quaternion_k;
            if (d < 0.0f)
                rtcQuaternionDecompositionSetQuaternion(&qd[k], -qd[k].quaternion_r, -qd[k].quaternion_i,
                                                        -qd[k].quaternion_j, -qd[k].quaternion_k);
        }
        instance_steps[i] = int(steps->size());
        rtcSetGeometryTimeStepCount(g, unsigned(steps->size()));
        for (size_t k = 0; k < steps->size(); ++k) {
            if (quaternions) {
                rtcSetGeometryTransformQuaternion(g, unsigned(k), &qd[k]);
            } else {
                float xfm[12];
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 4; ++c) xfm[r * 4 + c] = (*steps)[k].m[r][c];
                rtcSetGeometryTransform(g, unsigned(k), RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
            }
        }
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
    d.instance_steps.assign(scene.instances.size(), 1);
    d.mesh_steps.assign(scene.meshes.size(), 1);
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
        d.instance_geometry[i] = g;  // our reference, kept for update()
        d.set_instance_transform(uint32_t(i));
        d.attach(g, uint32_t(i));
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
        if (!d.mesh_vertices[m] || mesh.triangle_count() == 0) continue;
        d.update_mesh(m);
        top_changed = true;
    }
    for (uint32_t i : changes.moved_instances) {
        if (!d.instance_geometry[i]) continue;
        d.set_instance_transform(i);
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
    hit->time = time;
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

bool Accel::moving_transform(uint32_t instance, float time, Transform* object_to_world) const {
    const Impl& d = *m_impl;
    if (instance >= d.instance_steps.size() || d.instance_steps[instance] <= 1) return false;
    float xfm[12];
    rtcGetGeometryTransform(d.instance_geometry[instance], time, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) object_to_world->m[r][c] = xfm[r * 4 + c];
    return true;
}

bool Accel::mesh_deforms(uint32_t mesh) const { return mesh < m_impl->mesh_steps.size() && m_impl->mesh_steps[mesh] > 1; }

void Accel::triangle_world(uint32_t instance, uint32_t prim, Vec3* p0, Vec3* p1, Vec3* p2, float time) const {
    const Impl& d = *m_impl;
    const Instance& inst = d.scene.instances[instance];
    const Mesh& mesh = d.scene.meshes[inst.mesh];
    const uint32_t* idx = &mesh.indices[static_cast<size_t>(prim) * 3];
    const std::vector<Vec3>& baked = d.baked[instance];
    if (!baked.empty()) {
        *p0 = baked[idx[0]];
        *p1 = baked[idx[1]];
        *p2 = baked[idx[2]];
        return;
    }
    Vec3 q[3];
    if (d.mesh_steps[inst.mesh] > 1) {
        // Embree's interpolation of a vertex between time steps: (1 - f) a + f b.
        int k;
        float f;
        motion_segment(time, d.mesh_steps[inst.mesh], &k, &f);
        const MeshMotion& mm = d.scene.motion.meshes[inst.mesh];
        for (int j = 0; j < 3; ++j)
            q[j] = mm.positions[size_t(k)][idx[j]] * (1.0f - f) + mm.positions[size_t(k) + 1][idx[j]] * f;
    } else {
        for (int j = 0; j < 3; ++j) q[j] = mesh.positions[idx[j]];
    }
    Transform moving;
    const Transform& o2w = moving_transform(instance, time, &moving) ? moving : inst.object_to_world;
    *p0 = o2w.point(q[0]);
    *p1 = o2w.point(q[1]);
    *p2 = o2w.point(q[2]);
}

}  // namespace veach
