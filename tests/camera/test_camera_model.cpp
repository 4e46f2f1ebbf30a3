// The camera as light tracing needs it: project() is the inverse of generate_ray(), the density
// of generated directions is pdf_dir_w, and the importance We is normalised as the film expects
// (each pixel's share of the integral of We cos over the image's solid angle is 1 / pixels, so a
// splat divided by the samples per pixel estimates the pixel's value).
#include <gtest/gtest.h>

#include <cmath>

#include "camera/camera_model.h"
#include "core/rng.h"

namespace veach {
namespace {

// A camera turned off every axis and moved off the origin, so no component of the basis is 0 or 1.
Camera tilted_camera(bool orthographic) {
    Camera c;
    c.name = "tilted";
    c.orthographic = orthographic;
    c.yfov = 0.9f;
    c.xmag = 1.5f;
    c.ymag = 0.75f;
    const float q[4] = {0.2f, -0.35f, 0.1f, 0.9f};
    const float n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    c.camera_to_world = translation(Vec3(1.5f, -2.0f, 3.0f)) * rotation_quaternion(q[0] / n, q[1] / n, q[2] / n, q[3] / n);
    return c;
}

constexpr int k_width = 64, k_height = 48;

TEST(CameraModel, ProjectInvertsGenerateRay) {
    for (bool ortho : {false, true}) {
        Camera c = tilted_camera(ortho);
        CameraModel cam(&c, Bounds3(), k_width, k_height);
        Rng rng(7, 1);
        for (int i = 0; i < 2000; ++i) {
            const float fx = rng.next_float() * k_width, fy = rng.next_float() * k_height;
            Vec3 o, d;
            cam.generate_ray(fx, fy, &o, &d);
            EXPECT_NEAR(length(d), 1.0f, 1e-5f);
            for (float distance : {0.1f, 1.0f, 25.0f}) {
                float px, py;
                ASSERT_TRUE(cam.project(o + d * distance, &px, &py)) << "ortho " << ortho << " at " << fx << "," << fy;
                EXPECT_NEAR(px, fx, 2e-3f * (1.0f + 0.1f * distance));
                EXPECT_NEAR(py, fy, 2e-3f * (1.0f + 0.1f * distance));
            }
        }
        // Behind the camera, and beside the film, nothing projects.
        Vec3 o, d;
        cam.generate_ray(0.5f * k_width, 0.5f * k_height, &o, &d);
        float px, py;
        EXPECT_FALSE(cam.project(o - d * 2.0f, &px, &py));
        Vec3 o2, d2;
        cam.generate_ray(-0.5f * k_width, 0.5f * k_height, &o2, &d2);  // a film position left of the image
        EXPECT_FALSE(cam.project(o2 + d2 * 3.0f, &px, &py));
    }
}

// Solid angle of the directions generated over the film rectangle [x0, x0 + w] x [y0, y0 + h],
// from the spherical triangles of its corners' directions (van Oosterom and Strackee).
double film_solid_angle(const CameraModel& cam, double x0, double y0, double w, double h) {
    Vec3 o, a, b, c, d;
    cam.generate_ray(static_cast<float>(x0), static_cast<float>(y0), &o, &a);
    cam.generate_ray(static_cast<float>(x0 + w), static_cast<float>(y0), &o, &b);
    cam.generate_ray(static_cast<float>(x0 + w), static_cast<float>(y0 + h), &o, &c);
    cam.generate_ray(static_cast<float>(x0), static_cast<float>(y0 + h), &o, &d);
    auto tri = [](const Vec3& p, const Vec3& q, const Vec3& r) {
        const double num = std::fabs(static_cast<double>(dot(p, cross(q, r))));
        const double den = 1.0 + dot(p, q) + dot(q, r) + dot(r, p);
        return 2.0 * std::atan2(num, den);
    };
    return tri(a, b, c) + tri(a, c, d);
}

TEST(CameraModel, DirectionDensityIsTheFilmsJacobian) {
    // Uniform film positions have density 1 / pixels; the solid angle a small film patch spans
    // turns it into the density of directions, which pdf_dir_w must give.
    Camera c = tilted_camera(false);
    CameraModel cam(&c, Bounds3(), k_width, k_height);
    for (float fx : {0.5f, 13.0f, 32.0f, 63.5f}) {
        for (float fy : {0.5f, 24.0f, 47.5f}) {
            // A pixel-sized patch: smaller ones lose the float directions' precision, and the
            // density varies across one pixel by less than 1e-4.
            const double h = 1.0;
            const double omega = film_solid_angle(cam, fx - h / 2, fy - h / 2, h, h);
            const double expected = (h * h / (k_width * k_height)) / omega;
            Vec3 o, d;
            cam.generate_ray(fx, fy, &o, &d);
            EXPECT_NEAR(cam.pdf_dir_w(d) / expected, 1.0, 2e-3) << fx << "," << fy;
        }
    }
}

// The integral of We cos over the directions of the film rectangle [x0, x1] x [y0, y1], by the
// midpoint rule on an n x n grid of film cells (each cell's solid angle measured on the sphere).
double importance_over(const CameraModel& cam, double x0, double y0, double x1, double y1, int n) {
    double sum = 0;
    const double w = (x1 - x0) / n, h = (y1 - y0) / n;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double cx = x0 + (i + 0.5) * w, cy = y0 + (j + 0.5) * h;
            Vec3 o, d;
            cam.generate_ray(static_cast<float>(cx), static_cast<float>(cy), &o, &d);
            const double cos_theta = dot(d, cam.forward());
            sum += cam.importance(d) * cos_theta * film_solid_angle(cam, x0 + i * w, y0 + j * h, w, h);
        }
    }
    return sum;
}

TEST(CameraModel, ImportanceIntegratesToWhatTheFilmExpects) {
    Camera c = tilted_camera(false);
    CameraModel cam(&c, Bounds3(), k_width, k_height);
    // Over the whole image: 1.
    EXPECT_NEAR(importance_over(cam, 0, 0, k_width, k_height, 512), 1.0, 1e-3);
    // Over one pixel, at the centre and in the corners where cos^4 is smallest: 1 / pixels.
    for (auto [x, y] : {std::pair{32, 24}, std::pair{0, 0}, std::pair{63, 47}, std::pair{63, 0}}) {
        const double share = importance_over(cam, x, y, x + 1, y + 1, 16) * (k_width * k_height);
        EXPECT_NEAR(share, 1.0, 1e-3) << "pixel " << x << "," << y;
    }
    // None outside the image, nor behind the camera.
    Vec3 o, d;
    cam.generate_ray(-3.0f, 10.0f, &o, &d);
    EXPECT_EQ(cam.importance(d), 0.0f);
    EXPECT_EQ(cam.importance(-cam.forward()), 0.0f);
    // A delta camera has no importance to connect to.
    Camera oc = tilted_camera(true);
    CameraModel ortho(&oc, Bounds3(), k_width, k_height);
    EXPECT_EQ(ortho.importance(ortho.forward()), 0.0f);
}

}  // namespace
}  // namespace veach
