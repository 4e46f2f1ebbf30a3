#include "importers/gltf/gltf_image_use.h"

#include <cctype>

#include <nlohmann/json.hpp>

namespace veach::gltf {
namespace {

using nlohmann::json;

bool ends_with_texture(const std::string& key) {
    return key.size() >= 7 && (key.ends_with("Texture") || key.ends_with("texture"));
}

void collect_textures(const json& value, std::set<size_t>& textures) {
    if (value.is_array()) {
        for (const json& v : value) collect_textures(v, textures);
        return;
    }
    if (!value.is_object()) return;
    for (auto it = value.begin(); it != value.end(); ++it) {
        const json& v = it.value();
        if (ends_with_texture(it.key()) && v.is_object() && v.contains("index") && v["index"].is_number_unsigned())
            textures.insert(v["index"].get<size_t>());
        collect_textures(v, textures);
    }
}

void collect_sources(const json& texture, std::set<size_t>& images) {
    if (!texture.is_object()) return;
    if (texture.contains("source") && texture["source"].is_number_unsigned())
        images.insert(texture["source"].get<size_t>());
    if (texture.contains("extensions") && texture["extensions"].is_object())
        for (const json& ext : texture["extensions"])
            if (ext.is_object() && ext.contains("source") && ext["source"].is_number_unsigned())
                images.insert(ext["source"].get<size_t>());
}

// tinygltf decodes a URI as a form value ('+' is a space, %XX a byte) before it asks for the
// file, so the file callbacks see it decoded.
std::string percent_decoded(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i] == '+' ? ' ' : uri[i];
        }
    }
    return out;
}

std::string external_uri(const json& element) {
    if (!element.is_object() || !element.contains("uri") || !element["uri"].is_string()) return {};
    std::string uri = element["uri"].get<std::string>();
    return uri.starts_with("data:") ? std::string() : percent_decoded(uri);
}

}  // namespace

std::set<std::string> unused_image_uris(std::string_view text) {
    if (text.find("\"images\"") == std::string_view::npos) return {};
    json doc = json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("images") || !doc["images"].is_array()) return {};
    std::set<size_t> textures, used_images;
    if (doc.contains("materials")) collect_textures(doc["materials"], textures);
    if (doc.contains("textures") && doc["textures"].is_array())
        for (size_t t : textures)
            if (t < doc["textures"].size()) collect_sources(doc["textures"][t], used_images);
    std::set<std::string> needed, unused;
    const json& images = doc["images"];
    for (size_t i : used_images)
        if (i < images.size()) needed.insert(external_uri(images[i]));
    if (doc.contains("buffers") && doc["buffers"].is_array())
        for (const json& b : doc["buffers"]) needed.insert(external_uri(b));
    for (size_t i = 0; i < images.size(); ++i) {
        std::string uri = external_uri(images[i]);
        if (!uri.empty() && !used_images.count(i) && !needed.count(uri)) unused.insert(uri);
    }
    return unused;
}

}  // namespace veach::gltf
