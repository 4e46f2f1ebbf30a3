#include "materials/normal_map_microsurface.h"

#include <algorithm>
#include <cmath>

#include "core/rng.h"

namespace veach {

namespace {

// Which facet a walk is on.
enum class Facet : uint8_t { Perturbed, Tangent };

// The share of pdf_w given to a cosine lobe about the macro normal: the walks longer than two
// bounces, which the explicit terms leave out.
constexpr float k_cosine_floor = 0.2f;

// A ray arriving along -w on the mirror wall leaves along the reflection of w about wt.
Vec3 reflect_about(const Vec3& w, const Vec3& n) { return n * (2.0f * dot(w, n)) - w; }

}  // namespace

NormalMapMicrosurface::NormalMapMicrosurface(const Vec3& wp_in) {
    Vec3 wp = wp_in;
    float horizontal = std::sqrt(wp.x * wp.x + wp.y * wp.y);
    if (!(horizontal > 1e-5f) || !std::isfinite(horizontal)) return;  // the macro normal: no groove
    if (wp.z < k_min_cos) {
        float s = std::sqrt(1.0f - k_min_cos * k_min_cos) / horizontal;
        wp = Vec3(wp.x * s, wp.y * s, k_min_cos);
        horizontal = std::sqrt(1.0f - k_min_cos * k_min_cos);
    } else {
        wp = wp / length(wp);
        horizontal = std::sqrt(wp.x * wp.x + wp.y * wp.y);
    }
    m_wp = wp;
    m_sin_p = horizontal;
    m_wt = Vec3(-wp.x / horizontal, -wp.y / horizontal, 0.0f);
    m_p = Frame(wp);
    m_active = true;
}

float NormalMapMicrosurface::lambda_p(const Vec3& w) const {
    float ap = std::max(0.0f, dot(w, m_wp));
    float at = std::max(0.0f, dot(w, m_wt)) * m_sin_p;
    return ap + at > 0.0f ? ap / (ap + at) : 0.0f;
}

float NormalMapMicrosurface::g1(const Vec3& w) const {
    if (!(w.z > 0.0f)) return 0.0f;
    float cp = dot(w, m_wp), ct = dot(w, m_wt);
    // Both facets face w: nothing is hidden (the projected areas add up to w.z exactly; computed,
    // the ratio would be off by rounding).
    if (cp > 0.0f && ct >= 0.0f) return 1.0f;
    float sum = (std::max(0.0f, cp) + std::max(0.0f, ct) * m_sin_p) / m_wp.z;
    return sum > 0.0f ? std::min(1.0f, w.z / sum) : 0.0f;
}

Rgb NormalMapMicrosurface::next_event(const GltfBsdf& fp, const Vec3& a, const Vec3& wi, float g1_wi,
                                      TransportMode mode) const {
    Rgb sum(0.0f);
    Vec3 wi_p = m_p.to_local(wi);
    if (wi_p.z > 0.0f) sum += fp.eval(a, wi_p, mode) * (wi_p.z * g1_wi);
    // By the wall: leave along d = mirror_t(wi) toward it (<wi, wt> > 0), be stopped by it
    // (1 - G1(d)), leave the wall along wi.
    if (dot(wi, m_wt) > 0.0f) {
        Vec3 d = mirror_t(wi);
        Vec3 d_p = m_p.to_local(d);
        float blocked = 1.0f - g1(d);
        if (d_p.z > 0.0f && blocked > 0.0f) sum += fp.eval(a, d_p, mode) * (d_p.z * blocked * g1_wi);
    }
    return sum;
}

Rgb NormalMapMicrosurface::eval(const GltfBsdf& fp, const Vec3& wo, const Vec3& wi, uint64_t key,
                                TransportMode mode) const {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return Rgb(0.0f);
    Rng rng(mix64(key), key);
    const float g1_wi = g1(wi);
    const float lp = lambda_p(wo);
    Rgb sum(0.0f);
    // Both first facets, each with its probability, rather than one chosen at random.
    for (Facet start : {Facet::Perturbed, Facet::Tangent}) {
        Rgb weight(start == Facet::Perturbed ? lp : 1.0f - lp);
        if (!(weight.max() > 0.0f)) continue;
        Facet facet = start;
        Vec3 arriving = wo;  // back along the ray that reached the facet
        for (int event = 0; event < k_max_events; ++event) {
            Vec3 w;
            if (facet == Facet::Perturbed) {
                Vec3 a = m_p.to_local(arriving);
                if (!(a.z > 0.0f)) break;
                sum += weight * next_event(fp, a, wi, g1_wi, mode);
                BsdfSample s;
                if (!fp.sample(a, rng.next_float(), rng.next_float(), rng.next_float(), &s, mode) || !(s.wi.z > 0.0f))
                    break;
                weight *= s.weight;
                if (weight.is_black()) break;
                w = m_p.to_world(s.wi);
            } else {
                w = reflect_about(arriving, m_wt);
            }
            // Escaping here is a path next_event already counted (or a mirror's delta).
            float g = g1(w);
            if (g >= 1.0f || rng.next_float() < g) break;
            arriving = -w;
            facet = facet == Facet::Perturbed ? Facet::Tangent : Facet::Perturbed;
        }
    }
    return sum;
}

float NormalMapMicrosurface::pdf_w(const GltfBsdf& fp, const Vec3& wo, const Vec3& wi) const {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
    const float lp = lambda_p(wo);
    const float g1_wi = g1(wi);
    const Vec3 wi_p = m_p.to_local(wi);
    float p = 0.0f;
    if (lp > 0.0f) {
        Vec3 a = m_p.to_local(wo);
        float direct = wi_p.z > 0.0f ? fp.pdf_w(a, wi_p) * g1_wi : 0.0f;
        float by_wall = 0.0f;
        if (dot(wi, m_wt) > 0.0f) {
            Vec3 d = mirror_t(wi);
            Vec3 d_p = m_p.to_local(d);
            if (d_p.z > 0.0f) by_wall = fp.pdf_w(a, d_p) * (1.0f - g1(d)) * g1_wi;
        }
        p += lp * (direct + by_wall);
    }
    if (lp < 1.0f) {
        // The wall first: its mirror sends the ray down onto the perturbed facet.
        Vec3 a = m_p.to_local(mirror_t(wo));
        if (a.z > 0.0f && wi_p.z > 0.0f) p += (1.0f - lp) * fp.pdf_w(a, wi_p) * g1_wi;
    }
    return (1.0f - k_cosine_floor) * p + k_cosine_floor * wi.z * k_inv_pi;
}

bool NormalMapMicrosurface::sample(const GltfBsdf& fp, const Vec3& wo, float u_lobe, float u1, float u2,
                                   uint64_t key, TransportMode mode, BsdfSample* out) const {
    if (!(wo.z > 0.0f)) return false;
    Rng rng(mix64(key), key);
    const float lp = lambda_p(wo);
    Facet facet;
    float u = u_lobe;
    if (u < lp) {
        facet = Facet::Perturbed;
        u = std::min(u / lp, 1.0f - 0x1p-24f);
    } else {
        facet = Facet::Tangent;
    }
    bool fresh = true;  // (u, u1, u2) not used yet
    Rgb weight(1.0f);
    bool all_delta = true;
    float delta_pdf = 1.0f;
    Vec3 arriving = wo;
    for (int event = 0; event < k_max_events; ++event) {
        Vec3 w;
        if (facet == Facet::Perturbed) {
            Vec3 a = m_p.to_local(arriving);
            if (!(a.z > 0.0f)) return false;
            BsdfSample s;
            bool ok = fresh ? fp.sample(a, u, u1, u2, &s, mode)
                            : fp.sample(a, rng.next_float(), rng.next_float(), rng.next_float(), &s, mode);
            fresh = false;
            if (!ok || !(s.wi.z > 0.0f)) return false;
            weight *= s.weight;
            if (s.delta)
                delta_pdf *= s.pdf_w;
            else
                all_delta = false;
            w = m_p.to_world(s.wi);
        } else {
            w = reflect_about(arriving, m_wt);
        }
        float g = g1(w);
        if (g >= 1.0f || rng.next_float() < g) {
            out->wi = w;
            out->weight = weight;
            out->delta = all_delta;
            out->pdf_w = all_delta ? delta_pdf : pdf_w(fp, wo, w);
            return out->pdf_w > 0.0f && !weight.is_black();
        }
        arriving = -w;
        facet = facet == Facet::Perturbed ? Facet::Tangent : Facet::Perturbed;
    }
    return false;
}

}  // namespace veach
