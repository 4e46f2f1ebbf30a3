// A loaded scene re-posed between renders keeps its BVH and light tables (PreparedScene): what
// moved is updated in place, and a frame rendered that way is the frame a fresh load renders.
// pt's samples are keyed by (seed, pixel, sample), and the updated accel finds the same hits as
// one built for the frame (same transforms, same vertices), so the images are compared exactly.
#include <gtest/gtest.h>

#include <cstring>

#include "gltf_test_builder.h"
#include "importers/importer.h"
#include "integrators/prepared_scene.h"
#include "render_helpers.h"
#include "scene/scene_animation.h"
#include "scene/scene_changes.h"
#include "scene/scene_motion.h"

namespace veach {
namespace {

using namespace gltf_test;

void animate(GltfBuilder& b, int node, const char* path, const std::vector<float>& times,
             const std::vector<float>& values, const char* type) {
    int input = b.accessor(times, k_float, "SCALAR");
    int output = b.accessor(values, k_float, type);
    b.push("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}}},
                          {"samplers", {{{"input", input}, {"output", output}}}}});
}

int quad_mesh(GltfBuilder& b, float size, int material, bool morph = false) {
    const float h = size / 2;
    int pos = b.positions({-h, 0, -h, h, 0, -h, h, 0, h, -h, 0, h});
    int idx = b.accessor(std::vector<uint16_t>{0, 2, 1, 0, 3, 2}, k_ushort, "SCALAR");
    json prim = {{"attributes", {{"POSITION", pos}}}, {"indices", idx}, {"material", material}};
    json mesh = {{"primitives", json::array()}};
    if (morph) {  // one corner lifted by the target
        prim["targets"] = json::array({{{"POSITION", b.positions({0, 0, 0, 0, 0, 0, 0, h, 0, 0, 0, 0})}}});
        mesh["weights"] = {0.0};
    }
    mesh["primitives"].push_back(prim);
    return b.push("meshes", mesh);
}

// Static ground (baked), a box used twice (one copy static, one sliding: a shared BVH), a
// single-use card turning (its own BVH), a morphing sheet (refitted), an emissive panel and a
// point light that move when `moving_lights`.
GltfBuilder sequence_scene(bool moving_lights) {
    GltfBuilder b;
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.7, 0.6, 1}}, {"metallicFactor", 0}}}});
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
                         {"emissiveFactor", {4, 4, 3}}, {"doubleSided", true}});
    int ground = quad_mesh(b, 8, 0), box = quad_mesh(b, 1, 0), card = quad_mesh(b, 0.8f, 0),
        sheet = quad_mesh(b, 1.2f, 0, true), panel = quad_mesh(b, 0.6f, 1);
    b.place(ground);
    b.place(box, {{"translation", {-1.5, 0.5, -1}}});
    int sliding = b.place(box, {{"translation", {0, 0.5, -1}}});
    int turning = b.place(card, {{"translation", {1.5, 0.6, -1}}, {"rotation", {0.7071068, 0, 0, 0.7071068}}});
    int morphing = b.place(sheet, {{"translation", {0, 0.2, 0.5}}});
    int lamp = b.place(panel, {{"translation", {0, 2.5, 0}}, {"rotation", {1, 0, 0, 0}}});
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 683 * 20}}};
    int bulb = b.push("nodes", {{"translation", {2, 2, 1}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.doc["scenes"][0]["nodes"].push_back(bulb);
    b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.05}}}});
    int camera = b.push("nodes", {{"camera", 0}, {"translation", {0, 1.5, 4}}, {"rotation", {-0.2, 0, 0, 0.98}}});
    b.doc["scenes"][0]["nodes"].push_back(camera);
    animate(b, sliding, "translation", {0, 1}, {0, 0.5, -1, 0.8f, 0.5f, -0.6f}, "VEC3");
    animate(b, turning, "rotation", {0, 1}, {0.7071068f, 0, 0, 0.7071068f, 0, 0.7071068f, 0, 0.7071068f}, "VEC4");
    animate(b, morphing, "weights", {0, 1}, {0, 1}, "SCALAR");
    if (moving_lights) {
        animate(b, lamp, "translation", {0, 1}, {0, 2.5, 0, 1, 2, 0.5}, "VEC3");
        animate(b, bulb, "translation", {0, 1}, {2, 2, 1, -2, 2.5, 1}, "VEC3");
    }
    return b;
}

Scene load_at(const GltfBuilder& b, double t) {
    ImportOptions o;
    o.animate = true;
    Scene s = load(b, o);
    pose_scene(s, t);
    return s;
}

SceneChanges repose(Scene& s, double t) {
    const ScenePose before = capture_pose(s);
    pose_scene(s, t);
    return changes_since(before, s);
}

RenderJobOptions options() {
    RenderJobOptions o;
    o.width = 48;
    o.height = 32;
    o.render.spp = test::spp(4);
    o.render.integrator = "pt";
    o.render.max_depth = 4;
    o.render.threads = 2;
    return o;
}

bool identical(const Image& a, const Image& b) {
    return a.rgba.size() == b.rgba.size() && std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * 4) == 0;
}

TEST(SequenceUpdates, EveryFrameOfAReposedSceneEqualsAFreshLoadOfThatFrame) {
    for (bool lights : {false, true}) {
        const GltfBuilder b = sequence_scene(lights);
        Scene s = load_at(b, 0.0);
        PreparedSceneCache cache;
        Image first = render_scene(s, options(), {}, &cache).image;
        EXPECT_TRUE(identical(first, render_scene(load_at(b, 0.0), options()).image));
        for (double t : {0.25, 0.5, 1.0, 0.1}) {
            const SceneChanges changes = repose(s, t);
            EXPECT_FALSE(changes.moved_instances.empty());
            EXPECT_EQ(changes.deformed_meshes.size(), 1u);
            EXPECT_EQ(changes.lights_changed, lights);
            cache.note(changes);
            Image updated = render_scene(s, options(), {}, &cache).image;
            Image fresh = render_scene(load_at(b, t), options()).image;
            EXPECT_TRUE(identical(updated, fresh)) << "t = " << t << (lights ? " with moving lights" : "");
            EXPECT_FALSE(identical(updated, first)) << "t = " << t << ": nothing moved in the image";
        }
    }
}

TEST(SequenceUpdates, AMotionBlurredSequenceEqualsAFreshLoadOfEachFrame) {
    // With a shutter, each frame's motion steps are part of its pose: an update sets the moved
    // instances' time steps and the deformed meshes' step buffers. Past the last key (t = 2) the
    // steps vanish (nothing moves during the shutter) and come back at t = 0.5: the number of
    // time steps changes in place both ways.
    const double open = -0.1, close = 0.1;
    auto blurred_at = [&](const GltfBuilder& b, double t) {
        Scene s = load_at(b, t);
        capture_motion(s, t, open, close);
        return s;
    };
    const GltfBuilder b = sequence_scene(true);
    Scene s = blurred_at(b, 0.3);
    ASSERT_TRUE(s.motion.enabled());
    PreparedSceneCache cache;
    Image first = render_scene(s, options(), {}, &cache).image;
    EXPECT_TRUE(identical(first, render_scene(blurred_at(b, 0.3), options()).image));
    for (double t : {0.6, 2.0, 0.5, 0.95}) {
        const ScenePose before = capture_pose(s);
        pose_scene(s, t);
        capture_motion(s, t, open, close);
        const SceneChanges changes = changes_since(before, s);
        EXPECT_FALSE(changes.moved_instances.empty()) << t;
        cache.note(changes);
        Image updated = render_scene(s, options(), {}, &cache).image;
        Image fresh = render_scene(blurred_at(b, t), options()).image;
        EXPECT_TRUE(identical(updated, fresh)) << "t = " << t;
        EXPECT_EQ(s.motion.mesh_deforms(s.animation.deforming[0].mesh), t < 1.0) << t;
    }
}

TEST(SequenceUpdates, OnlyWhatMovedIsUpdatedAndLightTablesOnlyWhenAnEmitterMoved) {
    {
        Scene s = load_at(sequence_scene(false), 0.0);
        PreparedScene p(s);
        const Accel* accel = &p.accel();
        ASSERT_TRUE(p.update(repose(s, 0.5)));
        EXPECT_EQ(&p.accel(), accel) << "the accel is updated in place";
        // Nothing emissive moved and the bounds stayed (the ground spans them).
        EXPECT_EQ(p.light_builds(), 1);
        ASSERT_TRUE(p.update(repose(s, 0.5)));  // nothing changed at all
        EXPECT_EQ(p.light_builds(), 1);
    }
    {
        Scene s = load_at(sequence_scene(true), 0.0);
        PreparedScene p(s);
        ASSERT_TRUE(p.update(repose(s, 0.5)));
        EXPECT_EQ(p.light_builds(), 2) << "the emissive panel and the point light moved";
        // The static ground was baked into world space: the accel cannot follow it moving.
        SceneChanges ground;
        ground.moved_instances = {0};
        EXPECT_FALSE(p.update(ground));
    }
}

TEST(SequenceUpdates, AStaticSceneKeepsTheLayoutItAlwaysHad) {
    // Without animation nothing can move: no instance is movable and the accel is the one-level
    // BVH it always was (images of existing scenes unchanged).
    const GltfBuilder b = sequence_scene(true);
    Scene s = load(b);
    for (uint8_t m : movable_instances(s)) EXPECT_EQ(m, 0);
    Scene animated = load_at(b, 0.0);
    const std::vector<uint8_t> movable = movable_instances(animated);
    ASSERT_EQ(movable.size(), 6u);
    EXPECT_EQ(movable[0], 0) << "ground";
    EXPECT_EQ(movable[1], 0) << "the box that stays";
    EXPECT_EQ(movable[2], 1) << "the sliding box";
    EXPECT_EQ(movable[3], 1) << "the turning card";
    EXPECT_EQ(movable[4], 1) << "the morphing sheet";
    EXPECT_EQ(movable[5], 1) << "the moving panel";
}

TEST(SequenceUpdates, AnimatedMaterialsAndLightsThroughPointersUpdateTheLightTables) {
    // KHR_animation_pointer: the panel's emission strength and the bulb's intensity change, the
    // geometry stays. The light tables follow the new emission; each frame is a fresh load's.
    GltfBuilder b = sequence_scene(false);
    auto pointer = [&](const std::string& p, const std::vector<float>& values) {
        int input = b.accessor(std::vector<float>{0, 1}, k_float, "SCALAR");
        int output = b.accessor(values, k_float, "SCALAR");
        json target = {{"path", "pointer"}, {"extensions", {{"KHR_animation_pointer", {{"pointer", p}}}}}};
        b.push("animations", {{"channels", {{{"sampler", 0}, {"target", target}}}},
                              {"samplers", {{{"input", input}, {"output", output}}}}});
    };
    b.doc["animations"] = json::array();  // only the pointers move
    b.doc["extensionsUsed"].push_back("KHR_animation_pointer");
    b.doc["materials"][1]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 1.0;
    pointer("/materials/1/extensions/KHR_materials_emissive_strength/emissiveStrength", {1, 3});
    pointer("/extensions/KHR_lights_punctual/lights/0/intensity", {683 * 20, 683 * 5});
    Scene s = load_at(b, 0.0);
    PreparedSceneCache cache;
    Image first = render_scene(s, options(), {}, &cache).image;
    const SceneChanges changes = repose(s, 0.5);
    EXPECT_TRUE(changes.moved_instances.empty());
    EXPECT_TRUE(changes.lights_changed);
    cache.note(changes);
    Image updated = render_scene(s, options(), {}, &cache).image;
    EXPECT_TRUE(identical(updated, render_scene(load_at(b, 0.5), options()).image));
    EXPECT_FALSE(identical(updated, first));
    PreparedScene p(s);
    ASSERT_TRUE(p.update(repose(s, 1.0)));
    EXPECT_EQ(p.light_builds(), 2) << "the emission changed: the tables are rebuilt";
    ASSERT_TRUE(p.update(repose(s, 1.0)));
    EXPECT_EQ(p.light_builds(), 2) << "nothing changed";
}

}  // namespace
}  // namespace veach
