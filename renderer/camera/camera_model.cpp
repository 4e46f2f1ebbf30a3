#include "camera/camera_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "scene/scene_content_error.h"

namespace veach {

int CameraModel::default_height(const Camera* camera, int width) {
    float aspect = 16.0f / 9.0f;
    if (camera) {
        if (camera->orthographic && camera->xmag > 0 && camera->ymag > 0)
            aspect = camera->xmag / camera->ymag;
        else if (camera->aspect_ratio > 0)
            aspect = camera->aspect_ratio;
    }
    return std::max(1, static_cast<int>(std::lround(width / aspect)));
}

namespace {

// Unit vector along `v`, in double: the axes of a camera scaled by 1e-25 have a float length
// whose square underflows, and a 1e25 scale overflows it, yet their directions are exact.
bool unit_direction(const Vec3& v, Vec3* out) {
    const double x = v.x, y = v.y, z = v.z;
    const double l = std::sqrt(x * x + y * y + z * z);
    if (!(l > 0.0) || !std::isfinite(l)) return false;
    *out = Vec3(static_cast<float>(x / l), static_cast<float>(y / l), static_cast<float>(z / l));
    return true;
}

float max_abs(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

SceneContentError bad_camera(const Camera& camera, const std::string& fault) {
    return SceneContentError("camera '" + camera.name + "': " + fault);
}

}  // namespace

CameraModel::CameraModel(const Camera* camera, const Bounds3& bounds, int width, int height)
    : m_width(width), m_height(height) {
    float aspect = static_cast<float>(width) / static_cast<float>(height);
    if (camera) {
        const Transform& m = camera->camera_to_world;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c)
                if (!std::isfinite(m.m[r][c])) throw bad_camera(*camera, "its transform is not finite");
        m_origin = m.point(Vec3(0, 0, 0));
        if (!(max_abs(m_origin) <= k_max_ray_coordinate))
            throw bad_camera(*camera, "its position is too far from the scene's centre (over 1e18)");
        // Node scale does not change what a camera sees; a zero scale leaves no direction at all.
        Vec3 up, forward;
        if (!unit_direction(m.vector(Vec3(0, 1, 0)), &up) || !unit_direction(m.vector(Vec3(0, 0, -1)), &forward) ||
            !unit_direction(m.vector(Vec3(1, 0, 0)), &m_right))
            throw bad_camera(*camera, "its transform has a zero scale (no view direction)");
        // Re-orthogonalise: node matrices may carry shear or scale.
        if (!unit_direction(cross(forward, up), &m_right))
            throw bad_camera(*camera, "its up direction is parallel to its view direction");
        m_forward = forward;
        m_up = cross(m_right, m_forward);
        m_ortho = camera->orthographic;
        if (m_ortho) {
            // glTF's xmag/ymag are half extents; the image's aspect ratio decides the width.
            m_half_h = std::max(1e-12f, std::fabs(camera->ymag));
            m_half_w = m_half_h * aspect;
            if (!(max_abs(m_origin) + std::max(m_half_w, m_half_h) <= k_max_ray_coordinate))
                throw bad_camera(*camera, "its orthographic extent is too large (over 1e18)");
        } else {
            if (!std::isfinite(camera->yfov)) throw bad_camera(*camera, "its field of view is not finite");
            float yfov = clamp(camera->yfov, 1e-4f, k_pi - 1e-3f);
            m_half_h = std::tan(0.5f * yfov);
            m_half_w = m_half_h * aspect;
        }
    } else {
        // Frame the bounding sphere with a 40-degree vertical field of view from the front.
        Vec3 c = bounds.empty() ? Vec3() : bounds.center();
        float r = bounds.empty() ? 1.0f : std::max(1e-6f, 0.5f * length(bounds.diagonal()));
        float yfov = 0.6981317f;
        float fit = std::min(yfov, 2.0f * std::atan(std::tan(0.5f * yfov) * aspect));
        float dist = r / std::sin(0.5f * fit);
        m_origin = c + Vec3(0, 0, dist);
        if (!(max_abs(m_origin) <= k_max_ray_coordinate))
            throw SceneContentError(
                "the scene is too large for the default camera (it would stand over 1e18 from the origin); add a "
                "camera");
        m_forward = Vec3(0, 0, -1);
        m_right = Vec3(1, 0, 0);
        m_up = Vec3(0, 1, 0);
        m_half_h = std::tan(0.5f * yfov);
        m_half_w = m_half_h * aspect;
    }
    m_plane_area = 4.0f * m_half_w * m_half_h;
    m_pixel_size = 2.0f * m_half_h / static_cast<float>(std::max(1, m_height));
}

CameraModel CameraModel::interpolate(const CameraModel& a, const CameraModel& b, float s) {
    // The basis (right, up, -forward) is a proper rotation: right is cross(forward, up).
    auto rotation = [](const CameraModel& c) {
        Transform r;
        const Vec3 cols[3] = {c.m_right, c.m_up, -c.m_forward};
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i) r.m[i][k] = cols[k][i];
        return quaternion_of_rotation(r);
    };
    const std::array<float, 4> qa = rotation(a), qb = rotation(b);
    float q[4];
    slerp_quaternion(qa.data(), qb.data(), s, q);
    const Transform r = rotation_quaternion(q[0], q[1], q[2], q[3]);
    CameraModel c = a;
    c.m_origin = a.m_origin + (b.m_origin - a.m_origin) * s;
    c.m_right = r.vector(Vec3(1, 0, 0));
    c.m_up = r.vector(Vec3(0, 1, 0));
    c.m_forward = -r.vector(Vec3(0, 0, 1));
    c.m_half_w = a.m_half_w + (b.m_half_w - a.m_half_w) * s;
    c.m_half_h = a.m_half_h + (b.m_half_h - a.m_half_h) * s;
    c.m_plane_area = 4.0f * c.m_half_w * c.m_half_h;
    c.m_pixel_size = 2.0f * c.m_half_h / static_cast<float>(std::max(1, c.m_height));
    return c;
}

float CameraModel::footprint_width(float t, const Vec3& dir) const {
    if (m_ortho) return m_pixel_size;
    float c = std::max(0.0f, dot(dir, m_forward));
    return t * m_pixel_size * c * std::sqrt(c);
}

void CameraModel::generate_ray(float fx, float fy, Vec3* origin, Vec3* dir) const {
    float sx = (2.0f * fx / m_width - 1.0f) * m_half_w;
    float sy = (1.0f - 2.0f * fy / m_height) * m_half_h;
    if (m_ortho) {
        *origin = m_origin + m_right * sx + m_up * sy;
        *dir = m_forward;
    } else {
        *origin = m_origin;
        *dir = normalize(m_forward + m_right * sx + m_up * sy);
    }
}

float CameraModel::importance(const Vec3& dir) const {
    if (m_ortho) return 0.0f;  // light paths do not connect to an orthographic camera (a delta)
    float c = dot(dir, m_forward);
    if (c <= 0.0f) return 0.0f;
    float sx = dot(dir, m_right) / c, sy = dot(dir, m_up) / c;
    if (std::fabs(sx) > m_half_w || std::fabs(sy) > m_half_h) return 0.0f;
    float c2 = c * c;
    return 1.0f / (m_plane_area * c2 * c2);
}

float CameraModel::pdf_dir_w(const Vec3& dir) const {
    if (m_ortho) return 0.0f;
    float c = dot(dir, m_forward);
    if (c <= 0.0f) return 0.0f;
    return 1.0f / (m_plane_area * c * c * c);
}

bool CameraModel::project(const Vec3& p, float* fx, float* fy) const {
    Vec3 d = p - m_origin;
    float z = dot(d, m_forward);
    float sx, sy;
    if (m_ortho) {
        sx = dot(d, m_right);
        sy = dot(d, m_up);
        if (z <= 0.0f) return false;
    } else {
        if (z <= 0.0f) return false;
        sx = dot(d, m_right) / z;
        sy = dot(d, m_up) / z;
    }
    *fx = (sx / m_half_w + 1.0f) * 0.5f * m_width;
    *fy = (1.0f - sy / m_half_h) * 0.5f * m_height;
    return *fx >= 0.0f && *fy >= 0.0f && *fx < m_width && *fy < m_height;
}

}  // namespace veach
