// Chi-square goodness-of-fit of a direction sampler against its claimed density: the sphere is
// cut into a (cos theta, phi) grid of equal-solid-angle cells, expected counts come from
// integrating pdf_w over each cell numerically, cells with few expected samples are pooled, and
// the statistic's p-value must exceed the significance level (Bonferroni-corrected by the caller).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "core/math.h"
#include "core/rng.h"

namespace veach::test {

// Regularised upper incomplete gamma Q(a, x) by series / continued fraction (Numerical Recipes'
// formulation of the standard expansions).
inline double gamma_q(double a, double x) {
    if (x <= 0) return 1.0;
    double gln = std::lgamma(a);
    if (x < a + 1) {
        double sum = 1.0 / a, del = sum, ap = a;
        for (int n = 0; n < 1000; ++n) {
            ap += 1;
            del *= x / ap;
            sum += del;
            if (std::fabs(del) < std::fabs(sum) * 1e-15) break;
        }
        return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
    }
    double b = x + 1 - a, c = 1e300, d = 1 / b, h = d;
    for (int i = 1; i < 1000; ++i) {
        double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::fabs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (std::fabs(c) < 1e-300) c = 1e-300;
        d = 1 / d;
        double del = d * c;
        h *= del;
        if (std::fabs(del - 1) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - gln) * h;
}

struct ChiSquareResult {
    double p_value = 0;
    double statistic = 0;
    int dof = 0;
    double missing_mass = 0;  // fraction of samples the sampler failed to produce, vs 1 - integral of pdf
};

// sample(rng, &dir) -> false when no direction; pdf(dir) -> density per solid angle.
inline ChiSquareResult chi_square_directions(const std::function<bool(Rng&, Vec3*)>& sample,
                                             const std::function<double(const Vec3&)>& pdf, int n_samples = 1000000,
                                             int theta_bins = 40, int phi_bins = 80, int sub = 6) {
    int cells = theta_bins * phi_bins;
    std::vector<double> observed(cells, 0.0), expected(cells, 0.0);
    Rng rng(1234, 5678);
    int produced = 0;
    auto cell_of = [&](const Vec3& d) {
        float z = clamp(d.z, -1.0f, 1.0f);
        int ti = std::min(theta_bins - 1, static_cast<int>((1.0f - z) * 0.5f * theta_bins));
        float phi = std::atan2(d.y, d.x);
        if (phi < 0) phi += 2 * k_pi;
        int pi = std::min(phi_bins - 1, static_cast<int>(phi / (2 * k_pi) * phi_bins));
        return ti * phi_bins + pi;
    };
    for (int i = 0; i < n_samples; ++i) {
        Vec3 d;
        if (!sample(rng, &d)) continue;
        ++produced;
        observed[cell_of(d)] += 1;
    }
    // Integrate the pdf over each cell with a sub x sub midpoint rule in (z, phi): equal solid
    // angle (densities with sharp edges, a light's outline, need a finer rule).
    double cell_solid_angle = 4.0 * k_pi / cells;
    for (int ti = 0; ti < theta_bins; ++ti)
        for (int pi = 0; pi < phi_bins; ++pi) {
            double sum = 0;
            for (int a = 0; a < sub; ++a)
                for (int b = 0; b < sub; ++b) {
                    double z = 1.0 - 2.0 * (ti + (a + 0.5) / sub) / theta_bins;
                    double phi = 2 * k_pi * (pi + (b + 0.5) / sub) / phi_bins;
                    double r = std::sqrt(std::max(0.0, 1 - z * z));
                    sum += pdf(Vec3(static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                                    static_cast<float>(z)));
                }
            expected[ti * phi_bins + pi] = sum / (sub * sub) * cell_solid_angle * n_samples;
        }
    // Pool cells with expected count below 5 (sorted by expectation) into one.
    std::vector<int> order(cells);
    for (int i = 0; i < cells; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
    ChiSquareResult res;
    double pool_obs = 0, pool_exp = 0;
    int used = 0;
    for (int i : order) {
        if (expected[i] < 5.0) {
            pool_obs += observed[i];
            pool_exp += expected[i];
            continue;
        }
        double d = observed[i] - expected[i];
        res.statistic += d * d / expected[i];
        ++used;
    }
    if (pool_exp > 0) {
        double d = pool_obs - pool_exp;
        res.statistic += d * d / pool_exp;
        ++used;
    } else if (pool_obs > 0) {
        res.statistic = 1e30;  // samples where the density says none can be
    }
    res.dof = std::max(1, used - 1);
    res.p_value = gamma_q(0.5 * res.dof, 0.5 * res.statistic);
    double total_expected = 0;
    for (double e : expected) total_expected += e;
    res.missing_mass = std::fabs((n_samples - produced) - (n_samples - total_expected)) / n_samples;
    return res;
}

}  // namespace veach::test
