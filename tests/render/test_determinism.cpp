// Randomness is keyed by (seed, pixel, sample index): the thread count cannot change the image.
#include <gtest/gtest.h>

#include "importers/importer.h"
#include "render_helpers.h"

namespace veach {
namespace {

TEST(Determinism, OneAndTwoThreadsGiveBitIdenticalImages) {
    Scene s = import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf");
    Image one = test::render(s, 48, 8, "pt", 64, 1, 3);
    Image two = test::render(s, 48, 8, "pt", 64, 2, 3);
    ASSERT_EQ(one.rgba.size(), two.rgba.size());
    EXPECT_EQ(0, std::memcmp(one.rgba.data(), two.rgba.data(), one.rgba.size() * sizeof(float)));
    // And the seed matters: a different seed gives a different (noisy) image.
    Image other = test::render(s, 48, 8, "pt", 64, 2, 4);
    EXPECT_NE(0, std::memcmp(one.rgba.data(), other.rgba.data(), one.rgba.size() * sizeof(float)));
}

}  // namespace
}  // namespace veach
