#include "importers/gltf/gltf_animation_pointer.h"

#include <nlohmann/json.hpp>

namespace veach::gltf {
namespace {

constexpr std::string_view k_extension = "KHR_animation_pointer";

// The pointer's segments ("/a/b" -> a, b), with JSON pointer escapes (~1 = '/', ~0 = '~').
std::vector<std::string> segments(const std::string& pointer) {
    std::vector<std::string> out;
    if (pointer.empty() || pointer[0] != '/') return out;
    std::string current;
    for (size_t i = 1; i <= pointer.size(); ++i) {
        if (i == pointer.size() || pointer[i] == '/') {
            out.push_back(current);
            current.clear();
        } else if (pointer[i] == '~' && i + 1 < pointer.size() && (pointer[i + 1] == '0' || pointer[i + 1] == '1')) {
            current += pointer[i + 1] == '0' ? '~' : '/';
            ++i;
        } else {
            current += pointer[i];
        }
    }
    return out;
}

// A non-negative array index as JSON pointer writes it (no sign, no leading zero), else -1.
int index_of(const std::string& s) {
    if (s.empty() || s.size() > 9 || (s.size() > 1 && s[0] == '0')) return -1;
    for (char c : s)
        if (c < '0' || c > '9') return -1;
    return std::stoi(s);
}

}  // namespace

std::vector<PointerChannel> read_pointer_channels(std::string_view text) {
    std::vector<PointerChannel> out;
    if (text.find(k_extension) == std::string_view::npos) return out;
    nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("animations") || !doc["animations"].is_array())
        return out;
    const nlohmann::json& animations = doc["animations"];
    for (size_t a = 0; a < animations.size(); ++a) {
        const nlohmann::json& anim = animations[a];
        if (!anim.is_object() || !anim.contains("channels") || !anim["channels"].is_array()) continue;
        for (const nlohmann::json& ch : anim["channels"]) {
            if (!ch.is_object() || !ch.contains("target") || !ch["target"].is_object()) continue;
            const nlohmann::json& target = ch["target"];
            if (!target.contains("extensions") || !target["extensions"].is_object()) continue;
            const nlohmann::json& extensions = target["extensions"];
            auto ext = extensions.find(std::string(k_extension));
            if (ext == extensions.end() || !ext->is_object()) continue;
            PointerChannel pc;
            pc.animation = a;
            pc.sampler = ch.contains("sampler") && ch["sampler"].is_number_integer() ? ch["sampler"].get<int>() : -1;
            if (ext->contains("pointer") && (*ext)["pointer"].is_string()) pc.pointer = (*ext)["pointer"].get<std::string>();
            out.push_back(std::move(pc));
        }
    }
    return out;
}

std::optional<PointerTarget> parse_animation_pointer(const std::string& pointer) {
    std::vector<std::string> s = segments(pointer);
    PointerTarget t;
    auto property = [&](AnimatedProperty p, int target) -> std::optional<PointerTarget> {
        if (target < 0) return std::nullopt;
        t.property = p;
        t.target = target;
        return t;
    };
    if (s.size() == 3 && s[0] == "nodes") {
        t.node = index_of(s[1]);
        if (t.node < 0) return std::nullopt;
        if (s[2] == "translation") t.path = AnimatedPath::Translation;
        else if (s[2] == "rotation") t.path = AnimatedPath::Rotation;
        else if (s[2] == "scale") t.path = AnimatedPath::Scale;
        else if (s[2] == "weights") t.path = AnimatedPath::Weights;
        else return std::nullopt;
        return t;
    }
    if (s.size() >= 3 && s[0] == "materials") {
        int m = index_of(s[1]);
        if (s.size() == 4 && s[2] == "pbrMetallicRoughness") {
            if (s[3] == "baseColorFactor") return property(AnimatedProperty::BaseColor, m);
            if (s[3] == "metallicFactor") return property(AnimatedProperty::Metallic, m);
            if (s[3] == "roughnessFactor") return property(AnimatedProperty::Roughness, m);
        }
        if (s.size() == 3 && s[2] == "emissiveFactor") return property(AnimatedProperty::EmissiveFactor, m);
        if (s.size() == 3 && s[2] == "alphaCutoff") return property(AnimatedProperty::AlphaCutoff, m);
        if (s.size() == 5 && s[2] == "extensions" && s[3] == "KHR_materials_emissive_strength" &&
            s[4] == "emissiveStrength")
            return property(AnimatedProperty::EmissiveStrength, m);
        return std::nullopt;
    }
    if (s.size() >= 5 && s[0] == "extensions" && s[1] == "KHR_lights_punctual" && s[2] == "lights") {
        int l = index_of(s[3]);
        if (s.size() == 5 && s[4] == "color") return property(AnimatedProperty::LightColor, l);
        if (s.size() == 5 && s[4] == "intensity") return property(AnimatedProperty::LightIntensity, l);
        if (s.size() == 6 && s[4] == "spot" && s[5] == "innerConeAngle") return property(AnimatedProperty::SpotInnerCone, l);
        if (s.size() == 6 && s[4] == "spot" && s[5] == "outerConeAngle") return property(AnimatedProperty::SpotOuterCone, l);
        return std::nullopt;
    }
    if (s.size() == 4 && s[0] == "cameras") {
        int c = index_of(s[1]);
        if (s[2] == "perspective" && s[3] == "yfov") return property(AnimatedProperty::CameraYfov, c);
        if (s[2] == "orthographic" && s[3] == "xmag") return property(AnimatedProperty::CameraXmag, c);
        if (s[2] == "orthographic" && s[3] == "ymag") return property(AnimatedProperty::CameraYmag, c);
    }
    return std::nullopt;
}

}  // namespace veach::gltf
