#include "textures/mip_pyramid.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>

#include "core/rgb.h"
#include "textures/texel_codec.h"

namespace veach {
namespace {

// The input texels one output texel of an n -> m reduction covers, with their weights. Output i
// spans [i n/m, (i+1) n/m) in input texels; in units of 1/m that is [i n, (i+1) n), so the
// overlaps are exact integers and the weights (overlap / n) sum to exactly 1 per output.
struct Tap {
    int first = 0, count = 0;
    std::array<float, 3> weight{};  // n/m <= 3 for m = floor(n/2), n >= 2: at most 3 (odd n) or 2
};

std::vector<Tap> box_taps(int n, int m) {
    std::vector<Tap> taps(static_cast<size_t>(m));
    if (m == n) {  // a size of 1 stays 1
        for (int i = 0; i < m; ++i) taps[i] = {i, 1, {1.0f, 0.0f, 0.0f}};
        return taps;
    }
    for (int i = 0; i < m; ++i) {
        int64_t lo = static_cast<int64_t>(i) * n, hi = lo + n;  // units of 1/m
        int first = static_cast<int>(lo / m);
        int last = static_cast<int>((hi - 1) / m);
        Tap& t = taps[i];
        t.first = first;
        t.count = last - first + 1;
        for (int j = first; j <= last; ++j) {
            int64_t overlap = std::min<int64_t>(static_cast<int64_t>(j + 1) * m, hi) -
                              std::max<int64_t>(static_cast<int64_t>(j) * m, lo);
            t.weight[j - first] = static_cast<float>(static_cast<double>(overlap) / n);
        }
    }
    return taps;
}

// sRGB decoding of float level 0 texels. 8-bit files are kept as bytes and decoded by
// texel_codec's table; a float texture may still hold k/255 values (made in code, or an 8-bit
// image from elsewhere), and for those a table avoids a pow per texel, which would dominate
// building a 4K pyramid.
class SrgbDecoder {
public:
    SrgbDecoder() {
        for (int k = 0; k < 256; ++k) {
            m_encoded[k] = k / 255.0f;
            m_linear[k] = srgb_to_linear(m_encoded[k]);
        }
    }
    float operator()(float v) const {
        if (v >= 0.0f && v <= 1.0f) {
            int k = static_cast<int>(v * 255.0f + 0.5f);
            if (m_encoded[k] == v) return m_linear[k];
        }
        return srgb_to_linear(v);
    }

private:
    std::array<float, 256> m_encoded{}, m_linear{};
};

// One reduction (w, h) -> (mw, mh) of texels of type T. `decode` turns an input texel's RGB
// value into linear float, `alpha` its alpha into float. Row by row: each output row filters its
// few input rows horizontally and sums them with the vertical weights, so the only buffer is one
// output row (and integer images are never copied to floats in full).
template <typename T, typename Decode, typename Alpha>
MipLevel reduce(int w, int h, const T* in, Decode decode, Alpha alpha) {
    MipLevel out;
    out.width = std::max(1, w / 2);
    out.height = std::max(1, h / 2);
    out.texels.assign(static_cast<size_t>(out.width) * out.height * 4, 0.0f);
    if (w % 2 == 0 && h % 2 == 0) {
        // The common case, the plain 2x2 box, without the tap tables (twice as fast on 4K images).
        for (int oy = 0; oy < out.height; ++oy) {
            const T* r0 = in + static_cast<size_t>(2 * oy) * w * 4;
            const T* r1 = r0 + static_cast<size_t>(w) * 4;
            float* dst = &out.texels[static_cast<size_t>(oy) * out.width * 4];
            for (int ox = 0; ox < out.width; ++ox, r0 += 8, r1 += 8, dst += 4) {
                for (int c = 0; c < 3; ++c)
                    dst[c] = 0.25f * (decode(r0[c]) + decode(r0[4 + c]) + decode(r1[c]) + decode(r1[4 + c]));
                dst[3] = 0.25f * (alpha(r0[3]) + alpha(r0[7]) + alpha(r1[3]) + alpha(r1[7]));
            }
        }
        return out;
    }
    std::vector<Tap> tx = box_taps(w, out.width), ty = box_taps(h, out.height);
    std::vector<float> row(static_cast<size_t>(out.width) * 4);
    for (int oy = 0; oy < out.height; ++oy) {
        float* dst = &out.texels[static_cast<size_t>(oy) * out.width * 4];
        const Tap& vy = ty[oy];
        for (int k = 0; k < vy.count; ++k) {
            const T* src = in + static_cast<size_t>(vy.first + k) * w * 4;
            for (int ox = 0; ox < out.width; ++ox) {
                const Tap& vx = tx[ox];
                float acc[4] = {0, 0, 0, 0};
                for (int j = 0; j < vx.count; ++j) {
                    const T* p = src + static_cast<size_t>(vx.first + j) * 4;
                    float wj = vx.weight[j];
                    acc[0] += wj * decode(p[0]);
                    acc[1] += wj * decode(p[1]);
                    acc[2] += wj * decode(p[2]);
                    acc[3] += wj * alpha(p[3]);  // alpha is always linear
                }
                for (int c = 0; c < 4; ++c) row[ox * 4 + c] = acc[c];
            }
            float wy = vy.weight[k];
            for (size_t i = 0; i < row.size(); ++i) dst[i] += wy * row[i];
        }
    }
    return out;
}

// An 8-bit level from its float version (which the next level is computed from).
void store_as_bytes(MipLevel& level, bool srgb) {
    level.texels8.resize(level.texels.size());
    for (size_t i = 0; i < level.texels.size(); ++i)
        level.texels8[i] = (srgb && i % 4 != 3) ? encode_srgb8(level.texels[i]) : encode_unorm8(level.texels[i]);
    level.srgb8 = srgb;
    std::vector<float>().swap(level.texels);
}

}  // namespace

std::vector<MipLevel> build_mip_levels(int width, int height, const TexelSource& texels, bool srgb) {
    std::vector<MipLevel> levels;
    if (width <= 0 || height <= 0 || texels.empty() || (width == 1 && height == 1)) return levels;
    auto same = [](float v) { return v; };
    if (texels.f32) {
        if (srgb) {
            SrgbDecoder decoder;
            levels.push_back(reduce(width, height, texels.f32, [&](float v) { return decoder(v); }, same));
        } else {
            levels.push_back(reduce(width, height, texels.f32, same, same));
        }
    } else if (texels.u8) {
        // The floats an image of k / 255 values gives: the same table lookups SrgbDecoder makes.
        const Unorm8Tables& t = unorm8_tables();
        auto unorm = [&](uint8_t k) { return t.unorm[k]; };
        if (srgb)
            levels.push_back(reduce(width, height, texels.u8, [&](uint8_t k) { return t.srgb_linear[k]; }, unorm));
        else
            levels.push_back(reduce(width, height, texels.u8, unorm, unorm));
    } else {
        auto unorm = [](uint16_t k) { return static_cast<float>(k) / 65535.0f; };
        if (srgb)
            levels.push_back(reduce(width, height, texels.u16, [&](uint16_t k) { return srgb_to_linear(unorm(k)); }, unorm));
        else
            levels.push_back(reduce(width, height, texels.u16, unorm, unorm));
    }
    // An 8-bit image's levels are computed from the previous level's floats and then stored as
    // bytes; only the level being reduced is held in float.
    const bool bytes = texels.u8 != nullptr;
    while (levels.back().width > 1 || levels.back().height > 1) {
        const MipLevel& prev = levels.back();
        MipLevel next = reduce(prev.width, prev.height, prev.texels.data(), same, same);
        if (bytes) store_as_bytes(levels.back(), srgb);
        levels.push_back(std::move(next));
    }
    if (bytes) store_as_bytes(levels.back(), srgb);
    return levels;
}

struct MipCache::State {
    std::once_flag once;
    std::atomic<bool> built{false};
    std::vector<MipLevel> levels;
};

MipCache::MipCache() : m_state(std::make_unique<State>()) {}
MipCache::MipCache(const MipCache&) : MipCache() {}
MipCache& MipCache::operator=(const MipCache& other) {
    if (this != &other) m_state = std::make_unique<State>();
    return *this;
}
MipCache::MipCache(MipCache&&) noexcept = default;
MipCache& MipCache::operator=(MipCache&&) noexcept = default;
MipCache::~MipCache() = default;

const std::vector<MipLevel>& MipCache::levels(int width, int height, const TexelSource& texels, bool srgb) const {
    static const std::vector<MipLevel> none;  // immutable: safe to share
    if (!m_state) return none;
    std::call_once(m_state->once, [&] {
        m_state->levels = build_mip_levels(width, height, texels, srgb);
        m_state->built.store(true, std::memory_order_release);
    });
    return m_state->levels;
}

bool MipCache::built() const { return m_state && m_state->built.load(std::memory_order_acquire); }

}  // namespace veach
