// KHR_animation_pointer: animation channels whose target is a JSON pointer into the file
// ("/materials/0/emissiveFactor") instead of a node and a path. Blender 4.x writes them for
// material factors, light colour and intensity and camera fields.
//
// Why the JSON is read here: tinygltf (Debian's 2.7) requires a target node and drops every
// channel without one, so these channels never reach its model. When the file names the
// extension, its JSON is read once more for just them.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene_animation.h"

namespace veach::gltf {

// A channel as the file gives it: its animation, its sampler in that animation, its pointer.
struct PointerChannel {
    size_t animation = 0;
    int sampler = -1;
    std::string pointer;
};

// Every channel with a KHR_animation_pointer target, in file order; empty when the JSON does not
// name the extension or does not parse (tinygltf reports that).
std::vector<PointerChannel> read_pointer_channels(std::string_view json);

// What a pointer animates. A node's translation, rotation, scale or weights becomes an ordinary
// node channel (`node` and `path` set); the properties of scene_animation.h's AnimatedProperty
// set `property` and `target`; anything else is nullopt (the caller warns and skips it).
struct PointerTarget {
    int node = -1;
    AnimatedPath path = AnimatedPath::Translation;
    std::optional<AnimatedProperty> property;
    int target = -1;
};
std::optional<PointerTarget> parse_animation_pointer(const std::string& pointer);

}  // namespace veach::gltf
