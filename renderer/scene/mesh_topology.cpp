#include "scene/mesh_topology.h"

#include <cstring>
#include <unordered_map>

namespace veach {

namespace {

struct PositionKey {
    uint32_t x, y, z;
    bool operator==(const PositionKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct PositionHash {
    size_t operator()(const PositionKey& k) const {
        uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
        h ^= (h >> 29) + k.y * 0xBF58476D1CE4E5B9ull;
        h ^= (h >> 32) + k.z * 0x94D049BB133111EBull;
        return static_cast<size_t>(h ^ (h >> 31));
    }
};

PositionKey key_of(const Vec3& p) {
    // +0 and -0 are one position.
    auto bits = [](float f) {
        if (f == 0.0f) f = 0.0f;
        uint32_t u;
        std::memcpy(&u, &f, sizeof u);
        return u;
    };
    return {bits(p.x), bits(p.y), bits(p.z)};
}

}  // namespace

bool is_closed_mesh(const Mesh& mesh) {
    if (mesh.triangle_count() == 0) return false;
    // Exporters split vertices along UV seams and sharp edges; the surface is closed or not by
    // its positions, so corners are welded by exact position first.
    std::unordered_map<PositionKey, uint32_t, PositionHash> ids;
    ids.reserve(mesh.positions.size());
    std::vector<uint32_t> welded(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        welded[i] = ids.emplace(key_of(mesh.positions[i]), static_cast<uint32_t>(ids.size())).first->second;
    std::unordered_map<uint64_t, uint32_t> edges;
    edges.reserve(mesh.indices.size());
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        for (int e = 0; e < 3; ++e) {
            uint32_t ia = mesh.indices[t + e], ib = mesh.indices[t + (e + 1) % 3];
            if (ia >= welded.size() || ib >= welded.size()) return false;
            uint32_t a = welded[ia], b = welded[ib];
            if (a == b) continue;  // a degenerate corner
            if (a > b) std::swap(a, b);
            ++edges[(static_cast<uint64_t>(a) << 32) | b];
        }
    }
    for (const auto& [edge, count] : edges)
        if (count % 2 != 0) return false;
    return !edges.empty();
}

}  // namespace veach
