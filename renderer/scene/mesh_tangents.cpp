#include "scene/mesh_tangents.h"

#include <cmath>

namespace veach {

void generate_tangents(Mesh* mesh, int texcoord) {
    const std::vector<Vec2>& uv = texcoord == 1 ? mesh->uv1 : mesh->uv0;
    const size_t n = mesh->positions.size();
    if (uv.size() != n || n == 0) return;
    std::vector<Vec3> tan(n), bit(n);
    std::vector<Vec3> face_normal_sum(n);
    for (size_t t = 0; t + 2 < mesh->indices.size(); t += 3) {
        const uint32_t* idx = &mesh->indices[t];
        Vec3 p[3] = {mesh->positions[idx[0]], mesh->positions[idx[1]], mesh->positions[idx[2]]};
        Vec2 w[3] = {uv[idx[0]], uv[idx[1]], uv[idx[2]]};
        Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
        float du1 = w[1].x - w[0].x, dv1 = w[1].y - w[0].y, du2 = w[2].x - w[0].x, dv2 = w[2].y - w[0].y;
        float det = du1 * dv2 - du2 * dv1;
        Vec3 fn = cross(e1, e2);
        if (!(std::fabs(det) > 0.0f) || !(length_squared(fn) > 0.0f)) continue;
        // Solve [e1 e2] = [dP/du dP/dv] [du1 du2; dv1 dv2] for the two derivatives.
        Vec3 dpdu = (e1 * dv2 - e2 * dv1) / det;
        Vec3 dpdv = (e2 * du1 - e1 * du2) / det;
        float lu = length(dpdu), lv = length(dpdv);
        if (!(lu > 0.0f) || !(lv > 0.0f) || !std::isfinite(lu) || !std::isfinite(lv)) continue;
        dpdu = dpdu / lu;
        dpdv = dpdv / lv;
        for (int c = 0; c < 3; ++c) {
            Vec3 a = p[(c + 1) % 3] - p[c], b = p[(c + 2) % 3] - p[c];
            float la = length(a), lb = length(b);
            if (!(la > 0.0f) || !(lb > 0.0f)) continue;
            float angle = std::acos(clamp(dot(a, b) / (la * lb), -1.0f, 1.0f));
            tan[idx[c]] += dpdu * angle;
            bit[idx[c]] -= dpdv * angle;  // the normal map's +Y: v grows downward in glTF
            face_normal_sum[idx[c]] += normalize(fn) * angle;
        }
    }
    mesh->tangents.resize(n);
    mesh->tangent_signs.resize(n);
    for (size_t i = 0; i < n; ++i) {
        Vec3 nrm = mesh->normals.size() == n ? mesh->normals[i] : face_normal_sum[i];
        float ln = length(nrm);
        nrm = ln > 0.0f ? nrm / ln : Vec3(0, 0, 1);
        Vec3 t = tan[i] - nrm * dot(nrm, tan[i]);
        float lt = length(t);
        if (!(lt > 1e-12f) || !std::isfinite(lt)) {
            t = Frame(nrm).s;  // no usable UV gradient: any tangent, the map can't be oriented
        } else {
            t = t / lt;
        }
        mesh->tangents[i] = t;
        mesh->tangent_signs[i] = dot(cross(nrm, t), bit[i]) < 0.0f ? -1.0f : 1.0f;
    }
}

}  // namespace veach
