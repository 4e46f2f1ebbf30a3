#include "importers/gltf/gltf_animation.h"

#include <climits>
#include <cmath>
#include <functional>

#include <tiny_gltf.h>

namespace veach::gltf {
namespace {

std::string node_label(const tinygltf::Model& model, size_t index) {
    const std::string& name = model.nodes[index].name;
    return "node " + std::to_string(index) + (name.empty() ? "" : " '" + name + "'");
}

bool valid_index(int i, size_t size) { return i >= 0 && static_cast<size_t>(i) < size; }

// Floats from doubles, each finite, exactly n of them (or none: `empty` says so).
bool take(const std::vector<double>& v, size_t n, float* out) {
    if (v.size() != n) return false;
    for (size_t i = 0; i < n; ++i) {
        if (!std::isfinite(v[i])) return false;
        out[i] = float(v[i]);
    }
    return true;
}

size_t target_count(const tinygltf::Model& model, int mesh) {
    if (!valid_index(mesh, model.meshes.size())) return 0;
    size_t n = 0;
    for (const tinygltf::Primitive& p : model.meshes[size_t(mesh)].primitives) n = std::max(n, p.targets.size());
    return n;
}

}  // namespace

void read_nodes(const tinygltf::Model& model, SceneAnimation& out, ImportContext& context) {
    const size_t n = model.nodes.size();
    out.rest.assign(n, NodePose{});
    out.parents.assign(n, -1);
    out.rest_weights.assign(n, {});
    for (size_t i = 0; i < n; ++i) {
        const tinygltf::Node& node = model.nodes[i];
        NodePose& p = out.rest[i];
        auto bad = [&](const char* field) {
            return GltfError(node_label(model, i) + ": " + field + " is not " +
                             (std::string(field) == "matrix" ? "16" : std::string(field) == "rotation" ? "4" : "3") +
                             " finite numbers");
        };
        if (!node.matrix.empty()) {
            double m[16];
            for (size_t k = 0; k < 16 && node.matrix.size() == 16; ++k) m[k] = node.matrix[k];
            float check[16];
            if (!take(node.matrix, 16, check)) throw bad("matrix");
            p.has_matrix = true;
            p.matrix = from_column_major(m);
        } else {
            float v[4];
            if (!node.translation.empty()) {
                if (!take(node.translation, 3, v)) throw bad("translation");
                p.translation = Vec3(v[0], v[1], v[2]);
            }
            if (!node.rotation.empty()) {
                if (!take(node.rotation, 4, v)) throw bad("rotation");
                p.rotation = {v[0], v[1], v[2], v[3]};
            }
            if (!node.scale.empty()) {
                if (!take(node.scale, 3, v)) throw bad("scale");
                p.scale = Vec3(v[0], v[1], v[2]);
            }
        }
        for (int child : node.children) {
            if (!valid_index(child, n))
                throw GltfError(node_label(model, i) + ": child " + std::to_string(child) + " does not exist");
            if (out.parents[size_t(child)] < 0 && size_t(child) != i) out.parents[size_t(child)] = int(i);
        }
        // Morph weights: the node's, else its mesh's, else zeros (glTF 3.7.2.2).
        size_t targets = target_count(model, node.mesh);
        std::vector<float>& w = out.rest_weights[i];
        const std::vector<double>* src = !node.weights.empty() ? &node.weights
                                         : valid_index(node.mesh, model.meshes.size())
                                             ? &model.meshes[size_t(node.mesh)].weights
                                             : nullptr;
        w.assign(targets, 0.0f);
        if (src && !src->empty()) {
            if (src->size() != targets)
                context.warn(node_label(model, i) + ": " + std::to_string(src->size()) + " morph weights for " +
                             std::to_string(targets) + " targets; the missing ones are 0");
            for (size_t k = 0; k < targets && k < src->size(); ++k)
                w[k] = std::isfinite((*src)[k]) ? float((*src)[k]) : 0.0f;
        }
    }
    // A cycle in the parents would never end a walk to the root.
    for (size_t i = 0; i < n; ++i) {
        size_t steps = 0;
        for (int p = out.parents[i]; p >= 0; p = out.parents[size_t(p)])
            if (++steps > n) throw GltfError(node_label(model, i) + " is its own ancestor");
    }
}

void read_skins(const tinygltf::Model& model, SceneAnimation& out, ImportContext& context) {
    for (size_t s = 0; s < model.skins.size(); ++s) {
        const tinygltf::Skin& src = model.skins[s];
        std::string what = "skin " + std::to_string(s) + (src.name.empty() ? "" : " '" + src.name + "'");
        SkinData skin;
        if (src.joints.empty()) throw GltfError(what + " has no joints");
        if (src.joints.size() > 65535) throw GltfError(what + " has more than 65535 joints");
        for (int j : src.joints) {
            if (!valid_index(j, model.nodes.size()))
                throw GltfError(what + ": joint node " + std::to_string(j) + " does not exist");
            skin.joints.push_back(j);
        }
        if (src.inverseBindMatrices >= 0) {
            skin.inverse_bind = read_matrix_accessor(model, src.inverseBindMatrices, what + " inverseBindMatrices", context);
            if (skin.inverse_bind.size() < skin.joints.size())
                throw GltfError(what + ": " + std::to_string(skin.inverse_bind.size()) + " inverseBindMatrices for " +
                                std::to_string(skin.joints.size()) + " joints");
            skin.inverse_bind.resize(skin.joints.size());
            for (const Transform& m : skin.inverse_bind)
                for (const auto& row : m.m)
                    for (float v : row)
                        if (!std::isfinite(v)) throw GltfError(what + ": an inverse bind matrix is not finite");
        } else {
            skin.inverse_bind.assign(skin.joints.size(), Transform{});
        }
        out.skins.push_back(std::move(skin));
    }
}

void read_animations(const tinygltf::Model& model, const std::string& selection,
                     const std::vector<PointerChannel>& pointers, size_t light_count, SceneAnimation& out,
                     ImportContext& context) {
    const AttributeFormat times_format{1, 1, false, false, false};
    // KHR_mesh_quantization allows normalised integers for rotations and weights (and any of its
    // types for translation and scale); floats always. Animated properties are floats.
    const AttributeFormat vec3_format{3, 3, true, true, true};
    const AttributeFormat rotation_format{4, 4, true, true, false};
    const AttributeFormat weights_format{1, 1, true, true, false};
    const AttributeFormat property_format{1, 4, false, false, false};
    for (size_t a = 0; a < model.animations.size(); ++a) {
        const tinygltf::Animation& src = model.animations[a];
        Animation anim;
        anim.name = src.name;
        std::string label = "animation " + std::to_string(a) + (src.name.empty() ? "" : " '" + src.name + "'");
        // Samplers are read as channels use them, each once, with the format its path needs.
        std::vector<int> sampler_slot(src.samplers.size(), -1);
        auto read_sampler = [&](int index, const AttributeFormat& format, const std::function<void(const std::string&)>& skip) {
            if (!valid_index(index, src.samplers.size())) {
                skip("names sampler " + std::to_string(index) + ", which does not exist");
                return -1;
            }
            if (sampler_slot[size_t(index)] >= 0) return sampler_slot[size_t(index)];
            const tinygltf::AnimationSampler& ss = src.samplers[size_t(index)];
            std::string swhat = label + " sampler " + std::to_string(index);
            AnimationSampler s;
            if (ss.interpolation == "LINEAR" || ss.interpolation.empty())
                s.interpolation = Interpolation::Linear;
            else if (ss.interpolation == "STEP")
                s.interpolation = Interpolation::Step;
            else if (ss.interpolation == "CUBICSPLINE")
                s.interpolation = Interpolation::CubicSpline;
            else {
                skip("uses interpolation '" + ss.interpolation + "'");
                return -1;
            }
            FloatAccessor in = read_float_accessor(model, ss.input, times_format, swhat + " input", context);
            FloatAccessor values = read_float_accessor(model, ss.output, format, swhat + " output", context);
            bool ordered = in.count > 0;
            for (size_t k = 0; k < in.count; ++k)
                ordered = ordered && std::isfinite(in.values[k]) && (k == 0 || in.values[k] > in.values[k - 1]);
            if (!ordered) {
                skip("has key times that are not finite and strictly increasing");
                return -1;
            }
            size_t per_key = values.count / in.count;
            size_t elements = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
            if (values.count % (in.count * elements) != 0 || per_key < elements) {
                skip("has " + std::to_string(values.count) + " output values for " + std::to_string(in.count) + " keys");
                return -1;
            }
            for (float v : values.values)
                if (!std::isfinite(v)) {
                    skip("has output values that are not finite");
                    return -1;
                }
            s.times = std::move(in.values);
            // Weights: one scalar per morph target per key (three with tangents).
            s.components = values.components * int(per_key / elements);
            s.values = std::move(values.values);
            sampler_slot[size_t(index)] = int(anim.samplers.size());
            anim.samplers.push_back(std::move(s));
            return sampler_slot[size_t(index)];
        };
        // A node's translation, rotation, scale or weights, from a channel or a pointer.
        auto add_node_channel = [&](int node, AnimatedPath path, int sampler, const std::function<void(const std::string&)>& skip) {
            if (!valid_index(node, model.nodes.size())) {
                skip("targets node " + std::to_string(node) + ", which does not exist");
                return;
            }
            if (path != AnimatedPath::Weights && !model.nodes[size_t(node)].matrix.empty()) {
                skip("animates a node given by a matrix (glTF forbids it)");
                return;
            }
            const AttributeFormat& format = path == AnimatedPath::Rotation ? rotation_format
                                            : path == AnimatedPath::Weights ? weights_format
                                                                            : vec3_format;
            int slot = read_sampler(sampler, format, skip);
            if (slot < 0) return;
            if (path == AnimatedPath::Weights) {
                size_t targets = target_count(model, model.nodes[size_t(node)].mesh);
                if (size_t(anim.samplers[size_t(slot)].components) != targets) {
                    skip("has " + std::to_string(anim.samplers[size_t(slot)].components) +
                         " weights per key for a mesh of " + std::to_string(targets) + " morph targets");
                    return;
                }
            }
            anim.channels.push_back(AnimationChannel{node, path, slot});
        };
        for (size_t c = 0; c < src.channels.size(); ++c) {
            const tinygltf::AnimationChannel& ch = src.channels[c];
            std::string what = label + " channel " + std::to_string(c);
            auto skip = [&](const std::string& why) { context.warn(what + " " + why + "; ignored"); };
            AnimatedPath path;
            if (ch.target_path == "translation") path = AnimatedPath::Translation;
            else if (ch.target_path == "rotation") path = AnimatedPath::Rotation;
            else if (ch.target_path == "scale") path = AnimatedPath::Scale;
            else if (ch.target_path == "weights") path = AnimatedPath::Weights;
            else {
                skip("animates '" + ch.target_path + "'");
                continue;
            }
            add_node_channel(ch.target_node, path, ch.sampler, skip);
        }
        for (const PointerChannel& pc : pointers) {
            if (pc.animation != a) continue;
            std::string what = label + " channel animating " + (pc.pointer.empty() ? "no pointer" : pc.pointer);
            auto skip = [&](const std::string& why) { context.warn(what + " " + why + "; ignored"); };
            std::optional<PointerTarget> target = parse_animation_pointer(pc.pointer);
            if (!target) {
                skip("(KHR_animation_pointer) is not evaluated");
                continue;
            }
            if (!target->property) {
                add_node_channel(target->node, target->path, pc.sampler, skip);
                continue;
            }
            AnimatedProperty p = *target->property;
            size_t targets = p <= AnimatedProperty::AlphaCutoff    ? model.materials.size()
                             : p <= AnimatedProperty::SpotOuterCone ? light_count
                                                                    : model.cameras.size();
            if (!valid_index(target->target, targets)) {
                skip("points at something the file does not have");
                continue;
            }
            int slot = read_sampler(pc.sampler, property_format, skip);
            if (slot < 0) continue;
            int components = anim.samplers[size_t(slot)].components;
            if (components != animated_property_components(p)) {
                skip("has " + std::to_string(components) + " values per key for a property of " +
                     std::to_string(animated_property_components(p)));
                continue;
            }
            anim.properties.push_back(PropertyChannel{p, target->target, slot});
        }
        out.animations.push_back(std::move(anim));
    }

    out.selected = -1;
    if (selection.empty() || selection == "all") return;
    for (size_t a = 0; a < out.animations.size(); ++a)
        if (out.animations[a].name == selection) {
            out.selected = int(a);
            return;
        }
    bool digits = selection.find_first_not_of("0123456789") == std::string::npos && selection.size() < 10;
    if (digits && std::stoul(selection) < out.animations.size()) {
        out.selected = int(std::stoul(selection));
        return;
    }
    std::string known;
    for (size_t a = 0; a < out.animations.size(); ++a)
        known += (a ? ", " : "") + (out.animations[a].name.empty() ? "#" + std::to_string(a)
                                                                   : "'" + out.animations[a].name + "'");
    throw GltfError("no animation '" + selection + "' (" +
                    (known.empty() ? std::string("the file has no animations")
                                   : "animations: " + known + "; or an index, or all") +
                    ")");
}

std::shared_ptr<const std::vector<MorphTarget>> read_morph_targets(const tinygltf::Model& model,
                                                                   const tinygltf::Primitive& prim, size_t vertices,
                                                                   const std::string& what, ImportContext& context) {
    if (prim.targets.empty()) return nullptr;
    // Deltas may be quantised (KHR_mesh_quantization: normalised or plain integers).
    const AttributeFormat delta_format{3, 3, true, true, true};
    const AttributeFormat uv_delta_format{2, 2, true, true, false};
    const AttributeFormat color_delta_format{3, 4, true, true, false};
    auto targets = std::make_shared<std::vector<MorphTarget>>(prim.targets.size());
    auto finite = [](const float* v, int n) {
        for (int k = 0; k < n; ++k)
            if (!std::isfinite(v[k])) return false;
        return true;
    };
    for (size_t t = 0; t < prim.targets.size(); ++t) {
        MorphTarget& target = (*targets)[t];
        for (const auto& [name, accessor] : prim.targets[t]) {
            std::vector<Vec3>* dst = name == "POSITION" ? &target.positions
                                     : name == "NORMAL" ? &target.normals
                                     : name == "TANGENT" ? &target.tangents
                                                         : nullptr;
            std::vector<Vec2>* uv = name == "TEXCOORD_0" ? &target.uv0 : name == "TEXCOORD_1" ? &target.uv1 : nullptr;
            bool color = name == "COLOR_0";
            if (!dst && !uv && !color) continue;  // attributes the renderer does not read
            std::string where = what + " target " + std::to_string(t) + " " + name;
            FloatAccessor a = read_float_accessor(model, accessor,
                                                  dst ? delta_format : uv ? uv_delta_format : color_delta_format, where,
                                                  context);
            if (a.count != vertices)
                throw GltfError(where + ": " + std::to_string(a.count) + " elements, but POSITION has " +
                                std::to_string(vertices));
            const int c = a.components;
            // A non-finite delta moves nothing (the vertex keeps its value).
            if (dst) {
                dst->resize(vertices);
                for (size_t i = 0; i < vertices; ++i) {
                    const float* v = &a.values[3 * i];
                    (*dst)[i] = finite(v, 3) ? Vec3(v[0], v[1], v[2]) : Vec3(0, 0, 0);
                }
            } else if (uv) {
                uv->resize(vertices);
                for (size_t i = 0; i < vertices; ++i) {
                    const float* v = &a.values[2 * i];
                    (*uv)[i] = finite(v, 2) ? Vec2{v[0], v[1]} : Vec2{0, 0};
                }
            } else {
                target.colors.resize(vertices);
                for (size_t i = 0; i < vertices; ++i) {
                    const float* v = &a.values[size_t(c) * i];
                    target.colors[i] = finite(v, c) ? Rgba{v[0], v[1], v[2], c == 4 ? v[3] : 0.0f} : Rgba{0, 0, 0, 0};
                }
            }
        }
    }
    return targets;
}

void read_skin_influences(const tinygltf::Model& model, const tinygltf::Primitive& prim, size_t vertices,
                          size_t joint_count, const std::string& what, ImportContext& context, DeformingMesh& d) {
    // JOINTS_n: unsigned byte or short; WEIGHTS_n: float, or normalised unsigned byte or short.
    const AttributeFormat joints_format{4, 4, false, false, true};
    const AttributeFormat weights_format{4, 4, true, false, false};
    int sets = 0;
    while (prim.attributes.count("JOINTS_" + std::to_string(sets)) && prim.attributes.count("WEIGHTS_" + std::to_string(sets)))
        ++sets;
    d.influences = 4 * sets;
    if (sets == 0) return;
    context.charge(vertices * size_t(d.influences) * (sizeof(uint16_t) + sizeof(float)), what + " skin weights");
    d.joints.assign(vertices * size_t(d.influences), 0);
    d.weights.assign(vertices * size_t(d.influences), 0.0f);
    for (int s = 0; s < sets; ++s) {
        std::string jn = "JOINTS_" + std::to_string(s), wn = "WEIGHTS_" + std::to_string(s);
        FloatAccessor j = read_float_accessor(model, prim.attributes.at(jn), joints_format, what + " " + jn, context);
        FloatAccessor w = read_float_accessor(model, prim.attributes.at(wn), weights_format, what + " " + wn, context);
        if (j.count != vertices || w.count != vertices)
            throw GltfError(what + " " + jn + "/" + wn + ": " + std::to_string(std::min(j.count, w.count)) +
                            " elements, but POSITION has " + std::to_string(vertices));
        for (size_t i = 0; i < vertices; ++i)
            for (int k = 0; k < 4; ++k) {
                float joint = j.values[4 * i + size_t(k)], weight = w.values[4 * i + size_t(k)];
                if (!(weight > 0.0f) || !std::isfinite(weight)) continue;  // unused slot
                if (!(joint >= 0.0f) || size_t(joint) >= joint_count || joint != std::floor(joint))
                    throw GltfError(what + " " + jn + ": joint " + std::to_string(joint) + " of vertex " +
                                    std::to_string(i) + " is not one of the skin's " + std::to_string(joint_count));
                size_t slot = i * size_t(d.influences) + size_t(4 * s + k);
                d.joints[slot] = uint16_t(joint);
                d.weights[slot] = weight;
            }
    }
    // glTF requires the weights to sum to 1; exporters' rounding (or a file's fault) may not.
    bool renormalised = false;
    for (size_t i = 0; i < vertices; ++i) {
        float* w = &d.weights[i * size_t(d.influences)];
        double sum = 0;
        for (int k = 0; k < d.influences; ++k) sum += w[k];
        if (sum > 0 && std::fabs(sum - 1.0) > 2e-3) renormalised = true;
        if (sum > 0)
            for (int k = 0; k < d.influences; ++k) w[k] = float(w[k] / sum);
    }
    if (renormalised) context.warn(what + ": skin weights that do not sum to 1 were normalised");
}

}  // namespace veach::gltf
