#include <gtest/gtest.h>

#include "core/math.h"
#include "core/rgb.h"

namespace veach {
namespace {

TEST(Math, InverseUndoesAffineTransform) {
    Transform t =
        translation(Vec3(1, -2, 3)) * rotation_quaternion(0.1f, 0.7f, -0.2f, 0.6f) * scaling(Vec3(2, 3, 0.5f));
    Transform inv = inverse(t);
    Vec3 p(0.3f, -1.7f, 2.2f);
    Vec3 q = inv.point(t.point(p));
    EXPECT_NEAR(q.x, p.x, 1e-5);
    EXPECT_NEAR(q.y, p.y, 1e-5);
    EXPECT_NEAR(q.z, p.z, 1e-5);
}

TEST(Math, QuaternionRotatesAsGltfSays) {
    // 90 degrees about +Y maps +X to -Z.
    float s = std::sqrt(0.5f);
    Vec3 v = rotation_quaternion(0, s, 0, s).vector(Vec3(1, 0, 0));
    EXPECT_NEAR(v.x, 0, 1e-6);
    EXPECT_NEAR(v.z, -1, 1e-6);
}

TEST(Math, ColumnMajorMatrixPutsTranslationInLastColumn) {
    double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 6, 7, 1};
    Vec3 p = from_column_major(m).point(Vec3(0, 0, 0));
    EXPECT_FLOAT_EQ(p.x, 5);
    EXPECT_FLOAT_EQ(p.y, 6);
    EXPECT_FLOAT_EQ(p.z, 7);
}

TEST(Math, FrameIsOrthonormal) {
    for (Vec3 n : {Vec3(0, 0, 1), Vec3(0, 0, -1), normalize(Vec3(1, 2, 3)), normalize(Vec3(-0.3f, 0.1f, -0.9f))}) {
        Frame f(n);
        EXPECT_NEAR(dot(f.s, f.t), 0, 1e-6);
        EXPECT_NEAR(dot(f.s, f.n), 0, 1e-6);
        EXPECT_NEAR(length(f.s), 1, 1e-6);
        EXPECT_NEAR(length(f.t), 1, 1e-6);
        Vec3 v(0.2f, -0.5f, 0.8f);
        Vec3 w = f.to_world(f.to_local(v));
        EXPECT_NEAR(w.x, v.x, 1e-6);
    }
}

TEST(Math, SrgbTransferIsTheIecCurve) {
    EXPECT_NEAR(srgb_to_linear(0.5f), 0.2140411f, 1e-6);  // ((0.5+0.055)/1.055)^2.4
    EXPECT_NEAR(srgb_to_linear(0.04f), 0.04f / 12.92f, 1e-9);
    for (float v : {0.0f, 0.001f, 0.18f, 0.5f, 1.0f}) EXPECT_NEAR(srgb_to_linear(linear_to_srgb(v)), v, 1e-6);
}

}  // namespace
}  // namespace veach

namespace veach {
namespace {
// Rgb::max keeps std::fmax's semantics (the largest channel; a NaN channel is ignored, all-NaN
// is NaN): Russian roulette and the lobe floors rely on it.
TEST(Rgb, MaxIsFmaxOfTheChannels) {
    const float nan = std::nanf("");
    const float vals[] = {-1.0f, 0.0f, -0.0f, 0.5f, 2.0f, nan, INFINITY};
    for (float a : vals)
        for (float b : vals)
            for (float c : vals) {
                float want = std::fmax(a, std::fmax(b, c)), got = Rgb(a, b, c).max();
                if (std::isnan(want))
                    EXPECT_TRUE(std::isnan(got));
                else
                    EXPECT_EQ(want, got) << a << " " << b << " " << c;
            }
}
}  // namespace
}  // namespace veach
