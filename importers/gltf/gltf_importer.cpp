// glTF 2.0 into a Scene: tinygltf parses the JSON and loads buffers; everything it hands back
// is treated as untrusted and checked here (references, ranges, counts) before use.
#include "importers/gltf/gltf_importer.h"

#include <array>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <set>
#include <span>
#include <string_view>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <tiny_gltf.h>

#include "core/available_memory.h"
#include "core/content_hash.h"
#include "importers/gltf/gltf_accessors.h"
#include "importers/gltf/gltf_animation.h"
#include "importers/gltf/gltf_draco.h"
#include "importers/gltf/gltf_extensions.h"
#include "importers/gltf/gltf_image_use.h"
#include "importers/gltf/gltf_instancing.h"
#include "importers/gltf/gltf_json_chunk.h"
#include "importers/gltf/gltf_materials.h"
#include "importers/gltf/gltf_meshopt.h"
#include "importers/gltf/spec_range.h"
#include "scene/light_units.h"
#include "scene/mesh_tangents.h"

namespace veach {
namespace {

namespace fs = std::filesystem;
using gltf::GltfError;

constexpr int k_max_node_depth = 1024;
constexpr size_t k_max_node_visits = size_t(1) << 20;
// tinygltf converts extension JSON to its Value type recursively; refuse nesting deep enough
// to exhaust the stack before it gets there.
constexpr int k_max_json_nesting = 512;
constexpr uint64_t k_max_file_bytes = UINT_MAX;     // tinygltf takes 32-bit lengths
constexpr size_t k_max_elements = size_t(1) << 20;  // per top-level array (nodes, accessors, ...)

// Messages are one short line: tinygltf's errors come as several lines and may quote whole
// base64 data URIs or the raw bytes near a JSON syntax error, so lines are joined with "; ",
// base64-like runs cut short and the whole capped (more than core/one_line.h does).
std::string short_message(const std::string& text) {
    constexpr size_t k_max_run = 48, k_max_length = 600;
    auto is_base64 = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '/'; };
    std::string out;
    size_t run = 0;  // length of the current base64-like run
    for (char c : text) {
        if (c == '\n' || c == '\r') {
            if (!out.empty() && !out.ends_with("; ")) out += "; ";
            run = 0;
            continue;
        }
        run = is_base64(c) ? run + 1 : 0;
        if (run > k_max_run) {
            if (run == k_max_run + 1) out += "...";
            continue;
        }
        out += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
    }
    while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
    if (out.size() > k_max_length) out = out.substr(0, k_max_length) + "...";
    return out;
}

// ---------------------------------------------------------------------------------------------
// File access for tinygltf. It looks for an external file under the base directory we give it,
// then under the process's working directory. We give it this marker instead of a directory so
// resolve_uri can tell a URI from the working-directory fallback (never allowed) and apply our
// rules: URIs stay inside the glTF's folder unless the caller allows external files.
constexpr std::string_view k_uri_marker = "<veach-gltf-uri>/";

struct UriPolicy {
    fs::path base_dir;
    bool allow_external = false;
    std::string violation;  // the first refused URI, reported once tinygltf returns
    // Synthetic files served as zero bytes (uri -> size), never opened: EXT_meshopt_compression
    // fallback buffers the importer itself added to the file, and image files no material uses
    // (one byte each: tinygltf refuses an empty image; nothing decodes them).
    std::map<std::string, uint64_t> zero_files;
    uint64_t content_hash = 0;  // every file read so far, by content (Scene::content_hash)
    // Files that exist but could not be read, and why (uri -> reason): tinygltf only warns about
    // an image it could not read and leaves it empty, so the reason is given when it is decoded.
    std::map<std::string, std::string> uri_of_path, unreadable;
};

// The path resolve_uri returns for a synthetic file: not a path any file system has.
constexpr std::string_view k_zero_file_marker = "<veach-zero-file>/";

const uint64_t* zero_file_size(const std::string& path, void* user) {
    if (!path.starts_with(k_zero_file_marker)) return nullptr;
    const auto& files = static_cast<UriPolicy*>(user)->zero_files;
    auto it = files.find(path.substr(k_zero_file_marker.size()));
    return it == files.end() ? nullptr : &it->second;
}

// The folder a path really lies in: symbolic links resolved, so a link inside the scene's folder
// that points outside it is outside. A path that does not exist resolves as far as it exists.
fs::path real_path(const fs::path& p) {
    std::error_code ec;
    fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
    return ec ? p.lexically_normal() : r;
}

bool is_inside(const fs::path& path, const fs::path& folder) {
    auto f = folder.begin(), p = path.begin();
    for (; f != folder.end(); ++f, ++p) {
        if (f->empty()) continue;  // a trailing separator
        if (p == path.end() || *p != *f) return false;
    }
    return true;
}

std::string resolve_uri(const std::string& joined, void* user) {
    auto* policy = static_cast<UriPolicy*>(user);
    if (!joined.starts_with(k_uri_marker)) return {};
    std::string uri = joined.substr(k_uri_marker.size());
    // Data URIs of a type tinygltf doesn't decode, and remote URIs, are not files.
    if (uri.empty() || uri.starts_with("data:") || uri.find("://") != std::string::npos) return {};
    if (policy->zero_files.count(uri)) return std::string(k_zero_file_marker) + uri;
    auto refuse = [&](const char* why) {
        if (policy->violation.empty())
            policy->violation = "URI '" + uri + "' " + why + "; refused (external files are not allowed)";
        return std::string();
    };
    fs::path path(uri);
    if (path.is_absolute()) {
        if (!policy->allow_external) return refuse("is an absolute path");
        policy->uri_of_path[path.string()] = uri;
        return path.string();
    }
    fs::path normal = path.lexically_normal();
    if (!normal.empty() && *normal.begin() == ".." && !policy->allow_external)
        return refuse("leads outside the scene's folder");
    fs::path resolved = policy->base_dir / normal;
    if (!policy->allow_external && !is_inside(real_path(resolved), real_path(policy->base_dir)))
        return refuse("leads outside the scene's folder through a symbolic link");
    policy->uri_of_path[resolved.string()] = uri;
    return resolved.string();
}

bool file_exists(const std::string& path, void* user) {
    if (zero_file_size(path, user)) return true;
    // Anything that exists: read_bytes refuses what is not a regular file, with its reason.
    std::error_code ec;
    return !path.empty() && fs::exists(path, ec);
}

// Reads a whole regular file. FIFOs, devices, sockets and directories are refused without
// reading from them (a FIFO would block, /dev/zero never ends): the file is opened
// non-blocking and checked with fstat on the open descriptor, so what is checked is what is read.
bool read_bytes(const std::string& path, std::vector<unsigned char>& out, std::string& error) {
    int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        error = std::strerror(errno);
        return false;
    }
    struct FdCloser {
        int fd;
        ~FdCloser() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        error = std::strerror(errno);
        return false;
    }
    if (!S_ISREG(st.st_mode)) {
        error = S_ISDIR(st.st_mode) ? "is a directory" : "not a regular file";
        return false;
    }
    if (static_cast<uint64_t>(st.st_size) > k_max_file_bytes) {
        error = "file too large";
        return false;
    }
    // Reading it is the first allocation a file asks for: checked against what the process may
    // still take, so a file larger than memory is refused before it is read, not by bad_alloc.
    if (const uint64_t available = available_memory_bytes(); static_cast<uint64_t>(st.st_size) > available) {
        error = "reading it needs " + std::to_string(uint64_t(st.st_size) >> 20) + " MiB, more than the " +
                std::to_string(available >> 20) + " MiB of memory this process can take";
        return false;
    }
    out.resize(static_cast<size_t>(st.st_size));
    size_t done = 0;
    while (done < out.size()) {
        ssize_t n = ::read(fd, out.data() + done, out.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            error = n < 0 ? std::strerror(errno) : "the file shrank while it was read";
            return false;
        }
        done += static_cast<size_t>(n);
    }
    return true;
}

bool read_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    if (const uint64_t* size = zero_file_size(path, user)) {
        out->assign(size_t(*size), 0);
        return true;
    }
    std::string error;
    if (read_bytes(path, *out, error)) {
        auto* policy = static_cast<UriPolicy*>(user);
        policy->content_hash = fnv1a_64(out->data(), out->size(), policy->content_hash);
        return true;
    }
    auto* policy = static_cast<UriPolicy*>(user);
    if (auto it = policy->uri_of_path.find(path); it != policy->uri_of_path.end())
        policy->unreadable.emplace(it->second, error);
    if (err) *err += error;
    return false;
}

bool refuse_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing is not supported";
    return false;
}

// Images stay encoded until a rendered material uses them (MaterialConverter::decode). Images
// in a bufferView are left in the buffer: tinygltf hands us a pointer it did not bounds-check,
// so we must not touch it; the decoder reads the view after checking it.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void*) {
    if (image->bufferView >= 0) return true;
    if (size > 0) image->image.assign(bytes, bytes + size);
    image->as_is = true;
    return true;
}

// Parsing costs a multiple of the JSON text before any budget of ours can see what it holds:
// tinygltf's JSON document, the text's strings copied out of it, base64 data URIs decoded (a
// 419 MB data URI peaked at 2.26 GB resident: 5.4 bytes a byte), and a .glb's binary chunk
// copied into its buffer. Refused up front when that cannot fit in what the process may still
// take, instead of being OOM-killed half way through.
constexpr uint64_t k_parse_bytes_per_json_byte = 6;
constexpr uint64_t k_parse_bytes_per_binary_byte = 2;

void check_parse_memory(uint64_t json_bytes, uint64_t file_bytes) {
    const uint64_t binary_bytes = file_bytes > json_bytes ? file_bytes - json_bytes : 0;
    const uint64_t need = json_bytes * k_parse_bytes_per_json_byte + binary_bytes * k_parse_bytes_per_binary_byte;
    const uint64_t available = available_memory_bytes();
    if (need > available)
        throw GltfError("parsing this file needs about " + std::to_string(need >> 20) + " MiB, more than the " +
                        std::to_string(available >> 20) + " MiB of memory this process can take");
}

bool is_glb(std::span<const uint8_t> bytes) { return bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0; }

// The JSON text of a .gltf, or the JSON chunk of a .glb (clamped; tinygltf checks the header).
// What the JSON text says before tinygltf parses it. tinygltf materialises every element of
// every top-level array as a C++ object of a few hundred bytes (10 million empty nodes cost
// gigabytes before any check of ours could run) and converts extension JSON recursively (deep
// nesting exhausts the stack), so both are measured on the text first. glTF 1.0 is recognised
// here too: its top-level collections are dictionaries where 2.0 has arrays, and tinygltf
// would read it as an empty 2.0 scene.
struct JsonOutline {
    std::string version;                          // asset.version, when given
    bool dictionaries = false;                    // a glTF 1.0 style top-level dictionary
    std::map<std::string, size_t> array_lengths;  // elements of each top-level array
};

JsonOutline outline_json(std::string_view json) {
    static const std::set<std::string, std::less<>> k_collections = {
        "accessors", "bufferViews", "buffers", "cameras", "images",   "materials", "meshes",
        "nodes",     "samplers",    "scenes",  "skins",   "textures", "animations"};
    JsonOutline out;
    std::vector<char> open;           // '{' or '[' for each level
    std::vector<uint8_t> expect_key;  // per object level: the next string is a key
    bool in_string = false, escaped = false, string_is_key = false, value_next = false;
    std::string text, key1, key2;  // the current string; the last keys at depths 1 and 2
    size_t commas = 0;
    bool counting = false, nonempty = false;  // inside a top-level array
    for (char c : json) {
        const size_t depth = open.size();
        if (in_string) {
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"') {
                in_string = false;
                if (string_is_key) {
                    if (depth == 1) key1 = text;
                    if (depth == 2) key2 = text;
                } else if (depth == 2 && key1 == "asset" && key2 == "version") {
                    out.version = text;
                }
            } else if (depth <= 2 && text.size() < 64) {
                text += c;
            }
            continue;
        }
        if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
        if (counting && depth == 2 && !nonempty && c != ']') nonempty = true;
        if (value_next && depth == 1) {  // the first character of a top-level member's value
            if (c == '[') {
                counting = true;
                nonempty = false;
                commas = 0;
            } else if (c == '{' && k_collections.count(key1)) {
                out.dictionaries = true;
            }
        }
        value_next = false;
        switch (c) {
            case '"':
                in_string = true;
                string_is_key = !expect_key.empty() && open.back() == '{' && expect_key.back();
                text.clear();
                break;
            case ':':
                if (!expect_key.empty()) expect_key.back() = 0;
                value_next = true;
                break;
            case ',':
                if (!open.empty() && open.back() == '{') expect_key.back() = 1;
                if (counting && depth == 2) ++commas;
                break;
            case '{':
            case '[':
                if (open.size() >= size_t(k_max_json_nesting))
                    throw GltfError("JSON nested deeper than " + std::to_string(k_max_json_nesting) + " levels");
                open.push_back(c);
                expect_key.push_back(c == '{');
                break;
            case '}':
            case ']':
                if (open.empty()) break;  // malformed: tinygltf reports it
                open.pop_back();
                expect_key.pop_back();
                if (c == ']' && counting && open.size() == 1) {
                    out.array_lengths[key1] = nonempty ? commas + 1 : 0;
                    counting = false;
                }
                break;
            default: break;
        }
    }
    return out;
}

// Refuses, from the outline, what tinygltf must not be given: glTF 1.0, and more elements than
// any real scene holds (the node graph is walked once per node reference, so a million nodes is
// already far past what a renderable file carries).
void check_json_outline(const JsonOutline& outline, std::span<const uint8_t> bytes, bool binary) {
    uint32_t glb_version = 2;
    if (binary && bytes.size() >= 8) std::memcpy(&glb_version, bytes.data() + 4, 4);
    if (outline.dictionaries || outline.version.starts_with("1.") || glb_version == 1)
        throw GltfError("glTF 1.0 is not supported; convert to 2.0");
    size_t total = 0;
    for (const auto& [name, count] : outline.array_lengths) {
        if (count > k_max_elements)
            throw GltfError("'" + name + "' has " + std::to_string(count) + " elements, more than the " +
                            std::to_string(k_max_elements) + " a scene may hold");
        total += count;
    }
    if (total > 4 * k_max_elements)
        throw GltfError("the file declares " + std::to_string(total) + " objects, more than the " +
                        std::to_string(4 * k_max_elements) + " a scene may hold");
}

bool all_finite(const std::vector<double>& values) {
    for (double v : values)
        if (!std::isfinite(v)) return false;
    return true;
}

bool all_finite(const Transform& t) {
    for (const auto& row : t.m)
        for (float v : row)
            if (!std::isfinite(v)) return false;
    return true;
}

// A KHR_lights_punctual light definition, before a node places it.
struct LightDef {
    std::string name;
    std::optional<LightType> type;  // empty: unknown type, skipped
    Rgb color{1, 1, 1};
    double intensity = 1, range = 0;
    double inner_cone = 0, outer_cone = k_pi / 4;
    // VEACH_lights_blender (README, "Blender's lights"): what KHR_lights_punctual cannot carry.
    std::optional<AreaShape> area;  // an area light; the punctual type is only a fallback
    double size_x = 1, size_y = 1;  // area: metres in the light's local X and Y
    double power = 0;               // area: Blender's Power, W
    double radius = 0;              // point, spot: the sphere's radius, m
    double angle = 0;               // sun: angular diameter, radians
};

// ---------------------------------------------------------------------------------------------
class GltfImporter {
public:
    GltfImporter(const std::string& base_dir, const ImportOptions& options) : m_options(options) {
        m_uri_policy.base_dir = base_dir.empty() ? fs::path(".") : fs::path(base_dir);
        m_uri_policy.allow_external = options.allow_external_files;
    }

    Scene run(std::span<const uint8_t> bytes, bool binary, const std::string& display_name) {
        m_scene.source_path = display_name;
        m_uri_policy.content_hash = fnv1a_64(bytes.data(), bytes.size());
        load(bytes, binary);
        m_scene.content_hash = m_uri_policy.content_hash;
        check_extensions();
        m_materials = std::make_unique<gltf::MaterialConverter>(m_model, *m_context);
        m_materials->set_unreadable_images(m_uri_policy.unreadable);
        parse_lights();
        if (m_options.animate) {
            SceneAnimation& anim = m_scene.animation;
            anim.enabled = true;
            gltf::read_nodes(m_model, anim, *m_context);
            gltf::read_skins(m_model, anim, *m_context);
            gltf::read_animations(m_model, m_options.animation, m_pointer_channels, m_lights.size(), anim,
                                  *m_context);
            for (const LightDef& def : m_lights)
                anim.light_rest.push_back(LightRest{def.color, float(def.intensity), float(def.inner_cone),
                                                    float(def.outer_cone)});
        }
        m_mesh_entries.resize(m_model.meshes.size());
        m_mesh_uses.assign(m_model.meshes.size(), 0);
        m_visited.assign(m_model.nodes.size(), 0);
        m_on_path.assign(m_model.nodes.size(), 0);
        for (int root : root_nodes()) visit(root, Transform{}, 0, -1);
        if (m_options.animate) record_material_rest();
        finish();
        return std::move(m_scene);
    }

private:
    void load(std::span<const uint8_t> bytes, bool binary);
    void check_extensions();
    void parse_lights();
    void parse_blender_light(const tinygltf::Value* ext, const std::string& label, LightDef* def);
    std::vector<int> root_nodes();
    // `placement`: the parent's SceneAnimation placement (-1 at a root), when animating.
    void visit(int node_index, const Transform& parent, int depth, int placement);
    Transform local_transform(int node_index) const;
    void place_mesh(int node_index, const Transform& world, int placement);
    bool deforms(int node_index) const;
    std::optional<Mesh> build_primitive(int mesh_index, int primitive_index);
    std::vector<uint32_t> triangulate(int mode, const std::vector<uint32_t>& indices, const std::string& what);
    void add_camera(int node_index, const Transform& world);
    void add_light(int node_index, const tinygltf::Value& ref, const Transform& world, int placement);
    std::optional<PunctualLight> make_light(int node_index, const tinygltf::Value& ref, const Transform& world);
    // Rest values of the materials KHR_animation_pointer channels animate (after the visit,
    // when the materials the primitives use are converted).
    void record_material_rest();
    void finish();
    std::string node_label(int index) const {
        const std::string& name = m_model.nodes[index].name;
        return "node " + std::to_string(index) + (name.empty() ? "" : " '" + name + "'");
    }

    ImportOptions m_options;
    UriPolicy m_uri_policy;
    tinygltf::Model m_model;
    Scene m_scene;
    std::unique_ptr<gltf::ImportContext> m_context;
    std::unique_ptr<gltf::MaterialConverter> m_materials;
    std::vector<gltf::PointerChannel> m_pointer_channels;  // KHR_animation_pointer, read when animating
    std::vector<std::optional<std::vector<uint32_t>>> m_mesh_entries;  // glTF mesh -> Scene::meshes
    std::vector<int> m_mesh_uses;
    std::vector<uint8_t> m_visited, m_on_path;
    size_t m_visits = 0;
    std::vector<LightDef> m_lights;
    SpotFalloff m_spot_falloff = SpotFalloff::Gltf;
    bool m_blender_default_material = false;  // material-less primitives get Cycles' default surface
    int32_t m_blender_default_slot = -1;      // its Scene::materials index, made on first use
    int m_variant = -1;  // KHR_materials_variants index chosen by ImportOptions::variant
    size_t m_skipped_line_primitives = 0, m_dropped_triangles = 0;
    std::set<int> m_draco_indices;  // index accessors given a placeholder bufferView for tinygltf
    // Morph targets per (mesh, primitive), read once and shared by the nodes placing the mesh.
    std::map<std::pair<int, int>, std::shared_ptr<const std::vector<MorphTarget>>> m_targets;
};

void GltfImporter::load(std::span<const uint8_t> bytes, bool binary) {
    if (bytes.size() > k_max_file_bytes) throw GltfError("file too large (over 4 GiB)");
    if (binary) gltf::check_glb_layout(bytes);
    check_parse_memory(gltf::json_chunk(bytes, binary).size(), bytes.size());
    check_json_outline(outline_json(gltf::json_chunk(bytes, binary)), bytes, binary);
    std::optional<std::vector<uint8_t>> patched = gltf::patch_draco_index_accessors(bytes, binary, m_draco_indices);
    if (patched) {
        if (patched->size() > k_max_file_bytes) throw GltfError("file too large (over 4 GiB)");
        bytes = *patched;
    }
    if (m_options.animate) m_pointer_channels = gltf::read_pointer_channels(gltf::json_chunk(bytes, binary));
    for (const std::string& uri : gltf::unused_image_uris(gltf::json_chunk(bytes, binary)))
        m_uri_policy.zero_files.emplace(uri, 1);
    std::optional<std::vector<uint8_t>> with_fallbacks =
        gltf::give_meshopt_fallbacks_uris(bytes, binary, m_uri_policy.zero_files);
    if (with_fallbacks) {
        if (with_fallbacks->size() > k_max_file_bytes) throw GltfError("file too large (over 4 GiB)");
        bytes = *with_fallbacks;
    }

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&keep_encoded_image, nullptr);
    loader.SetFsCallbacks(tinygltf::FsCallbacks{&file_exists, &resolve_uri, &read_file, &refuse_write, &m_uri_policy});
    std::string err, warn;
    const std::string base(k_uri_marker.substr(0, k_uri_marker.size() - 1));
    auto size = static_cast<unsigned int>(bytes.size());
    bool ok = binary ? loader.LoadBinaryFromMemory(&m_model, &err, &warn, bytes.data(), size, base)
                     : loader.LoadASCIIFromString(&m_model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                                  size, base);
    if (!m_uri_policy.violation.empty()) throw GltfError(m_uri_policy.violation);
    if (!ok) {
        // nlohmann's parse errors start with an exception tag that means nothing to a user.
        if (err.starts_with("[json.exception.") && err.find("] ") != std::string::npos)
            err = "invalid JSON: " + err.substr(err.find("] ") + 2);
        throw GltfError(short_message(err.empty() ? "cannot parse the file" : err));
    }

    gltf::decode_meshopt_buffer_views(m_model);

    uint64_t input_bytes = bytes.size();
    for (const tinygltf::Buffer& b : m_model.buffers) input_bytes += b.data.size();
    for (const tinygltf::Image& i : m_model.images) input_bytes += i.image.size();
    m_context = std::make_unique<gltf::ImportContext>(m_scene, input_bytes);
}

void GltfImporter::check_extensions() {
    // The file's scenes, variants and animations by name, whatever is loaded of them.
    SceneCatalog& catalog = m_scene.catalog;
    for (const tinygltf::Scene& sc : m_model.scenes) catalog.scenes.push_back(sc.name);
    catalog.default_scene = m_model.defaultScene;
    for (const tinygltf::Animation& a : m_model.animations) catalog.animations.push_back(a.name);
    if (auto ext = m_model.extensions.find("KHR_materials_variants");
        ext != m_model.extensions.end() && ext->second.Has("variants") && ext->second.Get("variants").IsArray()) {
        const tinygltf::Value& list = ext->second.Get("variants");
        for (int i = 0; i < static_cast<int>(list.ArrayLen()); ++i) {
            const tinygltf::Value& v = list.Get(i);
            catalog.variants.push_back(v.Has("name") && v.Get("name").IsString() ? v.Get("name").Get<std::string>() : "");
        }
    }
    for (const std::string& name : m_model.extensionsRequired)
        if (!gltf::is_supported_extension(name)) throw GltfError("requires unsupported extension " + name);
    for (const std::string& name : m_model.extensionsUsed)
        if (!gltf::is_supported_extension(name)) m_context->warn("ignoring unsupported extension " + name);
    if (!m_options.variant.empty()) {
        // KHR_materials_variants: the root lists variant names; a name the file lacks is bad input.
        std::string known;
        auto ext = m_model.extensions.find("KHR_materials_variants");
        if (ext != m_model.extensions.end() && ext->second.Has("variants") && ext->second.Get("variants").IsArray()) {
            const tinygltf::Value& list = ext->second.Get("variants");
            for (int i = 0; i < static_cast<int>(list.ArrayLen()); ++i) {
                const tinygltf::Value& v = list.Get(i);
                if (!v.Has("name") || !v.Get("name").IsString()) continue;
                const std::string& name = v.Get("name").Get<std::string>();
                if (name == m_options.variant && m_variant < 0) m_variant = i;
                known += (known.empty() ? "'" : ", '") + name + "'";
            }
        }
        if (m_variant < 0)
            throw GltfError("no material variant '" + m_options.variant +
                            "' (variants: " + (known.empty() ? std::string("none") : known) + ")");
    }

    switch (m_options.spot_profile) {
        case SpotProfile::Blender: m_spot_falloff = SpotFalloff::Blender; break;
        case SpotProfile::Gltf: m_spot_falloff = SpotFalloff::Gltf; break;
        case SpotProfile::Auto:
            // Blender writes cone angles for its own spot profile, which differs from glTF's.
            m_spot_falloff =
                m_model.asset.generator.find("Blender") != std::string::npos ? SpotFalloff::Blender : SpotFalloff::Gltf;
            break;
    }
    // An object without a material is Cycles' default surface in Blender (and after Blender's
    // own glTF import, which makes no material for it), not the spec's white rough metal: a
    // Blender export renders as Blender showed it.
    switch (m_options.default_material) {
        case DefaultMaterial::Blender: m_blender_default_material = true; break;
        case DefaultMaterial::Gltf: m_blender_default_material = false; break;
        case DefaultMaterial::Auto:
            m_blender_default_material = m_model.asset.generator.find("Blender") != std::string::npos;
            break;
    }
}

// Blender's own light quantities, converted where the light is placed (add_light).
void GltfImporter::parse_blender_light(const tinygltf::Value* ext, const std::string& label, LightDef* def) {
    if (!ext || !ext->IsObject()) return;
    const tinygltf::Value* shape = gltf::json_member(ext, "shape");
    std::string shape_name = shape && shape->IsString() ? shape->Get<std::string>() : "";
    // "size": [x, y]; a square or a disk needs only x.
    double size[2] = {1, 1};
    const tinygltf::Value* size_value = gltf::json_member(ext, "size");
    bool one = size_value && size_value->IsArray() && size_value->ArrayLen() == 1;
    if (size_value && !gltf::json_numbers(size_value, size, one ? 1 : 2))
        m_context->warn(label + ": VEACH_lights_blender size is not [x, y] in metres; using 1 x 1");
    if (shape_name == "square" || shape_name == "rectangle" || shape_name == "disk" || shape_name == "ellipse") {
        bool round = shape_name == "disk" || shape_name == "ellipse";
        def->area = round ? AreaShape::Ellipse : AreaShape::Rectangle;
        def->size_x = std::max(0.0, size[0]);
        def->size_y = std::max(0.0, (shape_name == "square" || shape_name == "disk") ? size[0] : size[1]);
        def->power = gltf::in_range(gltf::json_number(ext, "power", 0.0), 0.0, double(k_max_light_intensity),
                                    "area light power", *m_context);
        double spread = gltf::json_number(ext, "spread", k_pi);
        if (std::fabs(spread - k_pi) > 1e-3)
            m_context->warn(label + ": area light spread of " + std::to_string(int(std::lround(spread * 180 / k_pi))) +
                            " degrees is not supported; rendered as 180 degrees");
        def->type = LightType::Area;
    } else if (!shape_name.empty() && shape_name != "point" && shape_name != "spot" && shape_name != "sun") {
        m_context->warn(label + ": VEACH_lights_blender shape '" + shape_name + "' is unknown; ignored");
    }
    def->radius = std::max(0.0, gltf::json_number(ext, "radius", 0.0));
    def->angle = std::clamp(gltf::json_number(ext, "angle", 0.0), 0.0, double(k_pi));
}

void GltfImporter::parse_lights() {
    const tinygltf::Value* ext = gltf::json_extension(m_model.extensions, "KHR_lights_punctual");
    const tinygltf::Value* lights = gltf::json_member(ext, "lights");
    if (!lights || !lights->IsArray()) return;
    for (size_t i = 0; i < lights->ArrayLen(); ++i) {
        const tinygltf::Value& v = lights->Get(static_cast<int>(i));
        LightDef def;
        std::string label = "light " + std::to_string(i);
        if (const tinygltf::Value* name = gltf::json_member(&v, "name"); name && name->IsString())
            def.name = name->Get<std::string>();
        const tinygltf::Value* type = gltf::json_member(&v, "type");
        std::string type_name = type && type->IsString() ? type->Get<std::string>() : "";
        if (type_name == "point")
            def.type = LightType::Point;
        else if (type_name == "spot")
            def.type = LightType::Spot;
        else if (type_name == "directional")
            def.type = LightType::Directional;
        else
            m_context->warn(label + " has unknown type '" + type_name + "'; ignored");
        std::array<double, 3> color = {1, 1, 1};
        if (gltf::json_member(&v, "color") && !gltf::json_numbers(gltf::json_member(&v, "color"), color.data(), 3))
            m_context->warn(label + " has an invalid color; using white");
        // The extension's ranges: colour in [0, 1], intensity non-negative (and at most
        // k_max_light_intensity): a negative light would render black, an overflowing one be lost.
        gltf::in_range(color, 0.0, 1.0, "light color", *m_context);
        def.color = Rgb(float(color[0]), float(color[1]), float(color[2]));
        def.intensity = gltf::in_range(gltf::json_number(&v, "intensity", 1.0), 0.0, double(k_max_light_intensity),
                                       "light intensity", *m_context);
        def.range = gltf::json_number(&v, "range", 0.0);
        const tinygltf::Value* spot = gltf::json_member(&v, "spot");
        def.inner_cone = gltf::json_number(spot, "innerConeAngle", 0.0);
        def.outer_cone = gltf::json_number(spot, "outerConeAngle", k_pi / 4);
        parse_blender_light(gltf::json_member(gltf::json_member(&v, "extensions"), "VEACH_lights_blender"), label,
                            &def);
        m_lights.push_back(def);
    }
}

std::vector<int> GltfImporter::root_nodes() {
    int count = static_cast<int>(m_model.scenes.size());
    int index = m_options.scene_index;
    if (index < -1 || index >= count || (index == -1 && m_model.defaultScene >= count))
        throw GltfError("scene " + std::to_string(index == -1 ? m_model.defaultScene : index) +
                        " does not exist (the file has " + std::to_string(count) + " scene" + (count == 1 ? "" : "s") +
                        ")");
    if (index == -1 && count > 0) index = m_model.defaultScene >= 0 ? m_model.defaultScene : 0;
    if (index >= 0) return m_model.scenes[index].nodes;

    // No scenes: the spec leaves rendering to the application; show every root node.
    if (m_model.nodes.empty()) return {};
    m_context->warn("the file has no scenes; rendering all root nodes");
    std::vector<uint8_t> has_parent(m_model.nodes.size(), 0);
    for (const tinygltf::Node& node : m_model.nodes)
        for (int child : node.children)
            if (child >= 0 && static_cast<size_t>(child) < has_parent.size()) has_parent[child] = 1;
    std::vector<int> roots;
    for (size_t i = 0; i < has_parent.size(); ++i)
        if (!has_parent[i]) roots.push_back(static_cast<int>(i));
    return roots;
}

void GltfImporter::visit(int node_index, const Transform& parent, int depth, int parent_placement) {
    if (node_index < 0 || static_cast<size_t>(node_index) >= m_model.nodes.size())
        throw GltfError("node " + std::to_string(node_index) + " does not exist (the file has " +
                        std::to_string(m_model.nodes.size()) + " nodes)");
    if (m_on_path[node_index]) throw GltfError("node " + std::to_string(node_index) + " is its own ancestor");
    if (depth >= k_max_node_depth)
        throw GltfError("node hierarchy is deeper than " + std::to_string(k_max_node_depth) + " levels");
    if (++m_visits > k_max_node_visits)
        throw GltfError("node hierarchy expands to more than " + std::to_string(k_max_node_visits) + " nodes");
    if (m_visited[node_index] == 1) {
        m_context->warn(node_label(node_index) +
                        " is reached more than once (glTF nodes have one parent); "
                        "placed each time");
        m_visited[node_index] = 2;  // said once
    } else if (m_visited[node_index] == 0) {
        m_visited[node_index] = 1;
    }

    const tinygltf::Node& node = m_model.nodes[node_index];
    Transform world = parent * local_transform(node_index);
    if (!all_finite(world)) throw GltfError(node_label(node_index) + " has a non-finite world transform");
    int placement = -1;
    if (m_options.animate) {
        placement = static_cast<int>(m_scene.animation.placements.size());
        m_scene.animation.placements.push_back(NodePlacement{node_index, parent_placement, {}, -1, -1, {}});
    }
    if (node.mesh != -1) place_mesh(node_index, world, placement);
    if (node.camera != -1) {
        size_t before = m_scene.cameras.size();
        add_camera(node_index, world);
        if (placement >= 0 && m_scene.cameras.size() > before)
            m_scene.animation.placements[size_t(placement)].camera = static_cast<int>(before);
    }
    if (const tinygltf::Value* light = gltf::json_extension(node.extensions, "KHR_lights_punctual"))
        add_light(node_index, *light, world, placement);

    m_on_path[node_index] = 1;
    for (int child : node.children) visit(child, world, depth + 1, placement);
    m_on_path[node_index] = 0;
}

Transform GltfImporter::local_transform(int node_index) const {
    const tinygltf::Node& node = m_model.nodes[node_index];
    auto check = [&](const std::vector<double>& v, size_t n, const char* field) {
        if (!v.empty() && v.size() != n)
            throw GltfError(node_label(node_index) + ": " + field + " has " + std::to_string(v.size()) +
                            " numbers, expected " + std::to_string(n));
        if (!all_finite(v)) throw GltfError(node_label(node_index) + ": " + field + " is not finite");
    };
    check(node.matrix, 16, "matrix");
    check(node.translation, 3, "translation");
    check(node.rotation, 4, "rotation");
    check(node.scale, 3, "scale");

    Transform t;
    if (!node.matrix.empty()) {
        t = from_column_major(node.matrix.data());  // takes precedence over TRS, as in the spec
    } else {
        const auto& tr = node.translation;
        const auto& r = node.rotation;  // quaternion x, y, z, w
        const auto& s = node.scale;
        if (!tr.empty()) t = translation(Vec3(float(tr[0]), float(tr[1]), float(tr[2])));
        if (!r.empty()) t = t * rotation_quaternion(float(r[0]), float(r[1]), float(r[2]), float(r[3]));
        if (!s.empty()) t = t * scaling(Vec3(float(s[0]), float(s[1]), float(s[2])));
    }
    if (!all_finite(t)) throw GltfError(node_label(node_index) + " has a non-finite transform");
    return t;
}

bool GltfImporter::deforms(int node_index) const {
    const tinygltf::Node& node = m_model.nodes[node_index];
    if (node.skin >= 0) return true;
    for (const tinygltf::Primitive& p : m_model.meshes[node.mesh].primitives)
        if (!p.targets.empty()) return true;
    return false;
}

void GltfImporter::place_mesh(int node_index, const Transform& world, int placement) {
    int mesh_index = m_model.nodes[node_index].mesh;
    if (mesh_index < 0 || static_cast<size_t>(mesh_index) >= m_model.meshes.size())
        throw GltfError(node_label(node_index) + ": mesh " + std::to_string(mesh_index) + " does not exist");
    std::optional<std::vector<Transform>> instances =
        gltf::read_gpu_instances(m_model, node_index, node_label(node_index), *m_context);
    if (placement >= 0 && deforms(node_index)) {
        // A deforming mesh gets its own Scene::Mesh per node: the weights and the skin are the
        // node's. The rest shape is placed by the node, as without animation.
        const tinygltf::Node& node = m_model.nodes[node_index];
        if (instances)
            m_context->warn(node_label(node_index) +
                            " deforms (skin or morph targets) and carries EXT_mesh_gpu_instancing: its mesh is "
                            "placed once, by the node");
        if (node.skin >= 0 && static_cast<size_t>(node.skin) >= m_model.skins.size())
            throw GltfError(node_label(node_index) + ": skin " + std::to_string(node.skin) + " does not exist");
        const auto& primitives = m_model.meshes[mesh_index].primitives;
        for (size_t p = 0; p < primitives.size(); ++p) {
            std::optional<Mesh> mesh = build_primitive(mesh_index, static_cast<int>(p));
            if (!mesh) continue;
            std::string what = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(p);
            DeformingMesh d;
            d.mesh = static_cast<uint32_t>(m_scene.meshes.size());
            d.instance = static_cast<uint32_t>(m_scene.instances.size());
            d.placement = placement;
            size_t n = mesh->positions.size();
            auto& targets = m_targets[{mesh_index, static_cast<int>(p)}];
            if (!targets) targets = gltf::read_morph_targets(m_model, primitives[p], n, what, *m_context);
            d.targets = targets;
            if (node.skin >= 0) {
                const SkinData& skin = m_scene.animation.skins[size_t(node.skin)];
                gltf::read_skin_influences(m_model, primitives[p], n, skin.joints.size(), what, *m_context, d);
                if (d.influences > 0)
                    d.skin = node.skin;
                else
                    m_context->warn(what + " is skinned but has no JOINTS_0/WEIGHTS_0; placed by its node");
            }
            m_scene.meshes.push_back(std::move(*mesh));
            m_scene.instances.push_back(Instance{d.mesh, world});
            m_scene.animation.deforming.push_back(std::move(d));
        }
        return;
    }
    // Each glTF mesh is converted once; every node using it adds instances of the same entries.
    auto& entries = m_mesh_entries[mesh_index];
    if (!entries) {
        entries.emplace();
        const auto& primitives = m_model.meshes[mesh_index].primitives;
        for (size_t p = 0; p < primitives.size(); ++p) {
            if (std::optional<Mesh> mesh = build_primitive(mesh_index, static_cast<int>(p))) {
                entries->push_back(static_cast<uint32_t>(m_scene.meshes.size()));
                m_scene.meshes.push_back(std::move(*mesh));
            }
        }
    }
    if (m_model.nodes[node_index].skin >= 0 && placement < 0)
        m_context->warn("skins are not supported; skinned meshes are placed by their node, in bind pose");
    if (++m_mesh_uses[mesh_index] > 1 && !entries->empty()) m_scene.features.instancing = true;
    if (!instances) {
        for (uint32_t entry : *entries) {
            if (placement >= 0)
                m_scene.animation.placements[size_t(placement)].instances.push_back(
                    static_cast<uint32_t>(m_scene.instances.size()));
            m_scene.instances.push_back(Instance{entry, world});
        }
        return;
    }
    // EXT_mesh_gpu_instancing: every instance of every primitive is a Scene instance of the one
    // mesh entry (the accel builds the mesh once and references it from each), placed by the
    // node's world transform times the instance's own.
    if (instances->size() > 1 && !entries->empty()) m_scene.features.instancing = true;
    m_context->charge(instances->size() * entries->size() * sizeof(Instance), node_label(node_index) + " instances");
    for (const Transform& local : *instances) {
        const Transform placed = world * local;
        if (!all_finite(placed))
            throw GltfError(node_label(node_index) + ": an EXT_mesh_gpu_instancing instance has a non-finite transform");
        for (uint32_t entry : *entries) {
            if (placement >= 0) {
                NodePlacement& pl = m_scene.animation.placements[size_t(placement)];
                pl.instances.push_back(static_cast<uint32_t>(m_scene.instances.size()));
                pl.instance_offsets.resize(pl.instances.size());  // identity for any placed before
                pl.instance_offsets.back() = local;
            }
            m_scene.instances.push_back(Instance{entry, placed});
        }
    }
}

std::optional<Mesh> GltfImporter::build_primitive(int mesh_index, int primitive_index) {
    const tinygltf::Mesh& src = m_model.meshes[mesh_index];
    const tinygltf::Primitive& prim = src.primitives[primitive_index];
    std::string what = "mesh " + std::to_string(mesh_index) + (src.name.empty() ? "" : " '" + src.name + "'") +
                       " primitive " + std::to_string(primitive_index);
    int mode = prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) {
        ++m_skipped_line_primitives;
        return std::nullopt;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
        throw GltfError(what + ": invalid mode " + std::to_string(mode));
    auto has = [&](const char* name) { return prim.attributes.count(name) != 0; };
    auto attribute = [&](const char* name) { return prim.attributes.at(name); };
    if (!prim.targets.empty() && !m_options.animate) m_context->warn("morph targets are not supported; meshes keep their base shape");
    if (!has("POSITION")) {
        m_context->warn(what + " has no POSITION; skipped");
        return std::nullopt;
    }
    // KHR_draco_mesh_compression: the attributes it lists and the indices come from its decoded
    // stream (the accessors only declare them); any other attribute is read as usual.
    std::unique_ptr<gltf::DracoPrimitive> draco = gltf::DracoPrimitive::decode(m_model, prim, what, *m_context);
    if (draco && mode == TINYGLTF_MODE_TRIANGLE_FAN)
        throw GltfError(what +
                        ": KHR_draco_mesh_compression allows mode TRIANGLES or TRIANGLE_STRIP, "
                        "not TRIANGLE_FAN");
    auto fetch = [&](const char* name, const gltf::AttributeFormat& format) {
        if (draco && draco->has(name)) return draco->read(m_model, attribute(name), name, format, what, *m_context);
        return gltf::read_float_accessor(m_model, attribute(name), format, what + " " + name, *m_context);
    };

    // Floats always; the integer forms are KHR_mesh_quantization's (and normalized u8/u16 for
    // texcoords and colours in core glTF).
    const gltf::AttributeFormat position_format{3, 3, true, true, true};
    const gltf::AttributeFormat normal_format{3, 3, false, true, false};
    const gltf::AttributeFormat texcoord_format{2, 2, true, true, true};
    const gltf::AttributeFormat color_format{3, 4, true, false, false};
    Mesh mesh;
    {
        gltf::FloatAccessor positions = fetch("POSITION", position_format);
        if (positions.count > UINT32_MAX) throw GltfError(what + ": too many vertices");
        mesh.positions.resize(positions.count);
        for (size_t i = 0; i < positions.count; ++i) {
            const float* p = &positions.values[3 * i];
            mesh.positions[i] = Vec3(p[0], p[1], p[2]);
        }
    }
    size_t n = mesh.positions.size();
    auto read = [&](const char* name, const gltf::AttributeFormat& format) {
        gltf::FloatAccessor a = fetch(name, format);
        if (a.count != n)
            throw GltfError(what + " " + name + ": " + std::to_string(a.count) + " elements, but POSITION has " +
                            std::to_string(n));
        return a;
    };

    mesh.name = src.name.empty() ? "mesh " + std::to_string(mesh_index) : src.name;
    if (src.primitives.size() > 1) mesh.name += "/" + std::to_string(primitive_index);
    if (has("NORMAL")) {  // absent: flat shading from the geometric normal
        gltf::FloatAccessor a = read("NORMAL", normal_format);
        mesh.normals.resize(n);
        for (size_t i = 0; i < n; ++i) {
            const float* v = &a.values[3 * i];
            mesh.normals[i] = Vec3(v[0], v[1], v[2]);
        }
    }
    // glTF's v = 0 is the top of the image, as is Texture's row 0: UVs are stored unchanged.
    for (int set = 0; set < 2; ++set) {
        std::string name = "TEXCOORD_" + std::to_string(set);
        if (!has(name.c_str())) continue;
        gltf::FloatAccessor a = read(name.c_str(), texcoord_format);
        std::vector<Vec2>& uv = set == 0 ? mesh.uv0 : mesh.uv1;
        uv.resize(n);
        for (size_t i = 0; i < n; ++i) uv[i] = Vec2{a.values[2 * i], a.values[2 * i + 1]};
    }
    if (has("COLOR_0")) {
        gltf::FloatAccessor a = read("COLOR_0", color_format);
        mesh.colors.resize(n);
        // A vertex colour multiplies the base colour, whose range is [0, 1]: float colours
        // outside it (a negative or huge multiplier, NaN) would make a surface reflect more than
        // it receives or a negative pixel, so they are held to it like the material's factors.
        bool out_of_range = false;
        auto unit = [&](float v) {
            if (v >= 0.0f && v <= 1.0f) return v;
            out_of_range = true;
            return v > 1.0f ? 1.0f : 0.0f;  // NaN and negatives to 0
        };
        for (size_t i = 0; i < n; ++i) {
            const float* c = &a.values[i * a.components];
            mesh.colors[i] = Rgba{unit(c[0]), unit(c[1]), unit(c[2]), a.components == 4 ? unit(c[3]) : 1.0f};
        }
        if (out_of_range) m_context->warn("COLOR_0 outside its range [0, 1] clamped");
    }

    std::vector<uint32_t> triangles;
    if (draco) {
        // Draco decodes faces, whatever the mode: a strip's triangles come out as a list.
        triangles = draco->triangles(m_model, prim.indices, mode == TINYGLTF_MODE_TRIANGLES, what, *m_context);
        for (uint32_t index : triangles)
            if (index >= n)
                throw GltfError(what + ": the Draco stream's index " + std::to_string(index) + " is past POSITION's " +
                                std::to_string(n) + " vertices");
    } else {
        std::vector<uint32_t> indices;
        if (prim.indices != -1) {
            if (m_draco_indices.count(prim.indices))
                throw GltfError(what + ": index accessor " + std::to_string(prim.indices) +
                                " has no bufferView (only a Draco-compressed primitive may use it)");
            indices = gltf::read_index_accessor(m_model, prim.indices, what + " indices", *m_context);
            for (uint32_t index : indices)
                if (index >= n)
                    throw GltfError(what + ": index accessor " + std::to_string(prim.indices) + " holds index " +
                                    std::to_string(index) + ", but POSITION has only " + std::to_string(n) +
                                    " vertices");
        } else {
            m_context->charge(n * sizeof(uint32_t), what);
            indices.resize(n);
            std::iota(indices.begin(), indices.end(), 0u);
        }
        triangles = triangulate(mode, indices, what);
    }

    // The renderer can't intersect a triangle with a NaN or infinite corner: drop those here.
    std::vector<uint8_t> bad(n, 0);
    bool any_bad = false;
    for (size_t i = 0; i < n; ++i) any_bad |= (bad[i] = !is_finite(mesh.positions[i])) != 0;
    if (any_bad) {
        size_t kept = 0;
        for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
            if (bad[triangles[t]] || bad[triangles[t + 1]] || bad[triangles[t + 2]]) {
                ++m_dropped_triangles;
                continue;
            }
            for (int k = 0; k < 3; ++k) triangles[kept++] = triangles[t + k];
        }
        triangles.resize(kept);
    }
    if (triangles.empty()) {
        m_context->warn(what + " has no triangles; skipped");
        return std::nullopt;
    }
    mesh.indices = std::move(triangles);

    // The chosen variant's material replaces the default where the primitive maps it.
    int material_index = prim.material;
    auto variants = prim.extensions.find("KHR_materials_variants");
    if (m_variant >= 0 && variants != prim.extensions.end() && variants->second.Has("mappings")) {
        const tinygltf::Value& mappings = variants->second.Get("mappings");
        for (int i = 0; mappings.IsArray() && i < static_cast<int>(mappings.ArrayLen()); ++i) {
            const tinygltf::Value& m = mappings.Get(i);
            if (!m.Has("material") || !m.Get("material").IsNumber() || !m.Has("variants")) continue;
            const tinygltf::Value& list = m.Get("variants");
            for (int k = 0; list.IsArray() && k < static_cast<int>(list.ArrayLen()); ++k)
                if (list.Get(k).IsNumber() && list.Get(k).GetNumberAsInt() == m_variant)
                    material_index = m.Get("material").GetNumberAsInt();
        }
    }
    if (material_index != -1) {
        if (material_index < 0 || static_cast<size_t>(material_index) >= m_model.materials.size())
            throw GltfError(what + ": material " + std::to_string(material_index) + " does not exist (the file has " +
                            std::to_string(m_model.materials.size()) + ")");
        mesh.material = m_materials->material(material_index);
    } else if (m_blender_default_material) {
        if (m_blender_default_slot < 0) {
            m_blender_default_slot = static_cast<int32_t>(m_scene.materials.size());
            m_scene.materials.push_back(Scene::blender_default_material());
        }
        mesh.material = m_blender_default_slot;
    }
    if (m_scene.material_of(mesh).is_emissive()) m_scene.features.emissive_meshes = true;
    if (!mesh.colors.empty()) m_scene.features.vertex_colors = true;
    // Tangent frames only for normal-mapped materials (the base's or the clearcoat's normal
    // texture): the file's TANGENT (xyz, handedness w), else generated from the normal texture's
    // UV set (the base's when both are present: one tangent frame per vertex).
    if (const Material& mat = m_scene.material_of(mesh);
        mat.normal_texture.valid() || (mat.clearcoat > 0.0f && mat.clearcoat_normal_texture.valid())) {
        if (has("TANGENT")) {
            gltf::FloatAccessor a = read("TANGENT", gltf::AttributeFormat{4, 4, false, true, false});
            mesh.tangents.resize(n);
            mesh.tangent_signs.resize(n);
            for (size_t i = 0; i < n; ++i) {
                const float* v = &a.values[4 * i];
                mesh.tangents[i] = Vec3(v[0], v[1], v[2]);
                mesh.tangent_signs[i] = v[3] < 0.0f ? -1.0f : 1.0f;
            }
        } else {
            generate_tangents(&mesh, mat.normal_texture.valid() ? mat.normal_texture.texcoord
                                                                : mat.clearcoat_normal_texture.texcoord);
        }
    }
    return mesh;
}

std::vector<uint32_t> GltfImporter::triangulate(int mode, const std::vector<uint32_t>& idx, const std::string& what) {
    std::vector<uint32_t> out;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (idx.size() % 3 != 0)
            m_context->warn(what + ": index count " + std::to_string(idx.size()) +
                            " is not a multiple of 3; the extra indices are ignored");
        out.assign(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(idx.size() / 3 * 3));
        return out;
    }
    if (idx.size() < 3) return out;
    size_t count = idx.size() - 2;
    m_context->charge(count * 3 * sizeof(uint32_t), what);
    out.reserve(count * 3);
    for (size_t i = 0; i < count; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            // Every other triangle of a strip is flipped to keep one winding (glTF spec 3.7.2.1).
            size_t odd = i % 2;
            out.insert(out.end(), {idx[i], idx[i + 1 + odd], idx[i + 2 - odd]});
        } else {
            out.insert(out.end(), {idx[i + 1], idx[i + 2], idx[0]});
        }
    }
    return out;
}

void GltfImporter::add_camera(int node_index, const Transform& world) {
    const tinygltf::Node& node = m_model.nodes[node_index];
    if (node.camera < 0 || static_cast<size_t>(node.camera) >= m_model.cameras.size())
        throw GltfError(node_label(node_index) + ": camera " + std::to_string(node.camera) + " does not exist");
    const tinygltf::Camera& src = m_model.cameras[node.camera];
    std::string label = "camera " + std::to_string(node.camera);
    Camera cam;
    cam.name = !src.name.empty() ? src.name : !node.name.empty() ? node.name : label;
    cam.camera_to_world = world;
    auto positive = [](double v) { return std::isfinite(v) && v > 0; };
    if (src.type == "perspective") {
        const tinygltf::PerspectiveCamera& p = src.perspective;
        if (positive(p.yfov) && p.yfov < k_pi)
            cam.yfov = float(p.yfov);
        else
            m_context->warn(label + " has an invalid yfov; using " + std::to_string(cam.yfov));
        cam.aspect_ratio = positive(p.aspectRatio) ? float(p.aspectRatio) : 0.0f;
        if (positive(p.znear)) cam.znear = float(p.znear);
        cam.zfar = positive(p.zfar) ? float(p.zfar) : 0.0f;
    } else if (src.type == "orthographic") {
        const tinygltf::OrthographicCamera& o = src.orthographic;
        cam.orthographic = true;
        if (std::isfinite(o.xmag) && o.xmag != 0 && std::isfinite(o.ymag) && o.ymag != 0) {
            cam.xmag = float(o.xmag);
            cam.ymag = float(o.ymag);
        } else {
            m_context->warn(label + " has an invalid xmag or ymag; using 1");
        }
        cam.znear = std::isfinite(o.znear) && o.znear >= 0 ? float(o.znear) : 0.0f;
        cam.zfar = positive(o.zfar) ? float(o.zfar) : 0.0f;
    } else {
        m_context->warn(label + " has unknown type '" + src.type + "'; ignored");
        return;
    }
    m_scene.cameras.push_back(cam);
    if (m_options.animate)
        m_scene.animation.camera_rest.push_back(CameraRest{node.camera, cam.yfov, cam.xmag, cam.ymag});
}

void GltfImporter::add_light(int node_index, const tinygltf::Value& ref, const Transform& world, int placement) {
    std::optional<PunctualLight> light = make_light(node_index, ref, world);
    if (!light) return;
    m_scene.lights.push_back(std::move(*light));
    m_scene.features.punctual_lights = true;
    if (placement < 0) return;
    // The light in its node's space, placed again by pose_scene at every time.
    int index = gltf::json_integer(&ref, "light", INT_MIN);
    const LightDef& def = m_lights[index];
    std::optional<PunctualLight> local = make_light(node_index, ref, Transform{});
    if (!local) return;
    SceneAnimation& anim = m_scene.animation;
    anim.placements[size_t(placement)].light = static_cast<int>(anim.lights.size());
    anim.lights.push_back(LocalLight{std::make_shared<const PunctualLight>(std::move(*local)),
                                     def.color * float(def.power / 4.0), index});
}

std::optional<PunctualLight> GltfImporter::make_light(int node_index, const tinygltf::Value& ref,
                                                      const Transform& world) {
    int index = gltf::json_integer(&ref, "light", INT_MIN);
    if (index < 0 || static_cast<size_t>(index) >= m_lights.size())
        throw GltfError(node_label(node_index) + ": KHR_lights_punctual light " + std::to_string(index) +
                        " does not exist (the file has " + std::to_string(m_lights.size()) + ")");
    const LightDef& def = m_lights[index];
    if (!def.type) return std::nullopt;  // unknown type, warned about once
    PunctualLight light;
    const std::string& node_name = m_model.nodes[node_index].name;
    light.name = !def.name.empty() ? def.name : !node_name.empty() ? node_name : "light " + std::to_string(index);
    light.type = *def.type;
    light.intensity = radiometric_intensity(def.color, def.intensity);
    light.position = world.point(Vec3(0, 0, 0));
    Vec3 axis = world.vector(Vec3(0, 0, -1));
    float len = length(axis);
    if (len > 0 && std::isfinite(len))
        light.direction = axis / len;
    else if (light.type != LightType::Point)
        m_context->warn(light.name + ": degenerate direction; using -Z");
    if (light.type == LightType::Spot) {
        set_spot_cone(light, def.inner_cone, def.outer_cone);
        light.falloff = m_spot_falloff;
    }
    light.range = def.range > 0 ? float(def.range) : 0.0f;
    if (light.type == LightType::Point || light.type == LightType::Spot) light.radius = float(def.radius);
    if (light.type == LightType::Directional) light.angle = float(def.angle);
    if (light.type == LightType::Area) {
        // Blender's area light: size along the local X and Y (scaled with the object, as Cycles
        // does), emitting along local -Z; Cycles gives power P over area A the radiance P / (4 A).
        light.shape = *def.area;
        light.axis_u = world.vector(Vec3(float(0.5 * def.size_x), 0, 0));
        light.axis_v = world.vector(Vec3(0, float(0.5 * def.size_y), 0));
        float area = length(cross(light.axis_u, light.axis_v)) * (light.shape == AreaShape::Rectangle ? 4.0f : k_pi);
        if (!(area > 0.0f) || !std::isfinite(area)) {
            m_context->warn(light.name + ": area light of zero size; ignored");
            return std::nullopt;
        }
        light.radiance = def.color * float(def.power / (4.0 * double(area)));
        light.intensity = Rgb(0.0f);
    }
    return light;
}

void GltfImporter::record_material_rest() {
    SceneAnimation& anim = m_scene.animation;
    bool any = false;
    for (const Animation& a : anim.animations)
        for (const PropertyChannel& p : a.properties) any = any || p.property <= AnimatedProperty::AlphaCutoff;
    if (!any) return;
    for (size_t m = 0; m < m_model.materials.size(); ++m) anim.material_rest.push_back(m_materials->rest(int(m)));
}

void GltfImporter::finish() {
    if (m_skipped_line_primitives > 0)
        m_context->warn("skipped " + std::to_string(m_skipped_line_primitives) +
                        " point/line primitives (only triangles are rendered)");
    if (m_dropped_triangles > 0)
        m_context->warn("dropped " + std::to_string(m_dropped_triangles) +
                        " triangles with non-finite vertex positions");
    if (m_scene.instances.empty()) m_context->warn("the scene has no geometry");
}

Scene import_bytes(std::span<const uint8_t> bytes, const std::string& base_dir, const std::string& display_name,
                   bool binary_expected, const ImportOptions& options) {
    try {
        bool binary = is_glb(bytes);
        if (binary_expected && !binary) throw GltfError("not a binary glTF file (no 'glTF' magic)");
        GltfImporter importer(base_dir, options);
        return importer.run(bytes, binary, display_name);
    } catch (const GltfError& e) {
        throw ImportError(display_name + ": " + short_message(e.what()));
    } catch (const ImportError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw ImportError(display_name + ": out of memory");
    } catch (const std::exception& e) {
        // tinygltf and nlohmann report some faults by throwing.
        throw ImportError(display_name + ": " + short_message(e.what()));
    }
}

}  // namespace

Scene import_gltf_file(const std::string& path, const ImportOptions& options) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw ImportError(path + ": file not found");
    if (fs::is_directory(path, ec)) throw ImportError(path + ": is a directory");
    if (!fs::is_regular_file(path, ec)) throw ImportError(path + ": not a regular file");
    std::vector<unsigned char> bytes;
    std::string error;
    if (!read_bytes(path, bytes, error)) throw ImportError(path + ": cannot read file (" + error + ")");
    return import_bytes(bytes, fs::path(path).parent_path().string(), path, false, options);
}

Scene import_gltf_memory(const std::vector<uint8_t>& bytes, const std::string& base_dir,
                         const std::string& display_name, bool binary, const ImportOptions& options) {
    return import_bytes(bytes, base_dir, display_name, binary, options);
}

}  // namespace veach
