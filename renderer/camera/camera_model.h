// The camera as the integrators see it: rays for film positions (and, for light tracing, the
// reverse: where a world point lands on the film and with what importance).
#pragma once

#include "core/math.h"
#include "scene/scene.h"

namespace veach {

class CameraModel {
public:
    // `camera` may be null: a default camera then frames `scene_bounds` from +Z. Throws
    // std::invalid_argument naming the camera when it gives no usable ray: a non-finite
    // transform, a zero scale, up parallel to forward, or rays starting past
    // k_max_ray_coordinate (a position or orthographic extent over 1e18).
    CameraModel(const Camera* camera, const Bounds3& scene_bounds, int width, int height);

    // Ray through film position (fx, fy) in pixels, (0, 0) the top-left corner of the image.
    void generate_ray(float fx, float fy, Vec3* origin, Vec3* dir) const;

    int width() const { return m_width; }
    int height() const { return m_height; }
    bool orthographic() const { return m_ortho; }
    const Vec3& position() const { return m_origin; }
    const Vec3& forward() const { return m_forward; }

    // Film position of a world point seen by a pinhole camera; false when behind the camera or
    // off the film.
    bool project(const Vec3& p, float* fx, float* fy) const;
    // Area of the image plane at distance 1 (pinhole): the pixel-to-solid-angle scale for We.
    float image_plane_area() const { return m_plane_area; }

    // Importance of a pinhole camera toward unit direction `dir` (Veach's We, normalised so
    // that the integral of We cos over the image's solid angle is 1): 1 / (A cos^4), with A the
    // image plane's area at distance 1. Zero outside the image.
    float importance(const Vec3& dir) const;
    // Solid-angle density of the camera ray direction `dir` when film positions are uniform:
    // 1 / (A cos^3).
    float pdf_dir_w(const Vec3& dir) const;

    // Ray cones for texture filtering (Amanatides 1984; Akenine-Moller et al. 2019, "Texture
    // Level of Detail Strategies for Real-Time Ray Tracing"): the angle one pixel spans at the
    // image centre (perspective), 2 tan(yfov/2) / height, and the width of one pixel's cone at
    // distance t along camera ray `dir` (unit). Off-axis a pixel spans the solid angle
    // spread^2 cos^3(theta), so the cone's width is t spread cos^1.5(theta); an orthographic
    // pixel is a tube of constant width.
    float pixel_spread_angle() const { return m_ortho ? 0.0f : m_pixel_size; }
    float footprint_width(float t, const Vec3& dir) const;

    // The camera a fraction s of the way from a to b (two motion steps of one camera: same
    // projection and film): position and extents linearly, orientation by slerp on the shorter
    // arc, so a camera turning at a constant rate between the steps is exact.
    static CameraModel interpolate(const CameraModel& a, const CameraModel& b, float s);

    // Default image height for a width: from the camera's aspect ratio (or 16:9).
    static int default_height(const Camera* camera, int width);

private:
    bool m_ortho = false;
    int m_width, m_height;
    Vec3 m_origin, m_right, m_up, m_forward;  // world basis, unit
    float m_half_w = 1, m_half_h = 1;         // tan(fov/2) extents (perspective) or xmag/ymag
    float m_plane_area = 4;
    float m_pixel_size = 0;  // a pixel's height on the image plane at distance 1 (or, orthographic, in the world)
};

}  // namespace veach
