// A feature-guided regression denoiser for Monte Carlo images, in the family of Rousselle et al.
// 2013 ("Robust Denoising using Feature and Color Information") and Bitterli et al. 2016 (NFOR,
// "Nonlinearly Weighted First-order Regression for Denoising Monte Carlo Renderings"):
//
//  - The render is kept as two independent half images, A (even sample indices) and B (odd), so
//    that the noise of each can be measured from their difference and the error of any filter
//    estimated without a reference.
//  - Each pixel's value is a weighted first-order regression over a window of its neighbours on
//    the features (albedo, normal, world position): a texture or a shading gradient that the
//    features explain is fitted, not averaged away. A fit is kept within the colours it leaned
//    on (weight over 0.1): at an edge no feature explains, a line may overshoot; the data do not.
//  - The regression weights come from colour alone (non-local means on patches), computed on the
//    other half: half A is fitted with weights from B and B with weights from A, so the weights
//    are not tuned to the very noise they average.
//  - Several candidate filters (weaker and stronger) and the unfiltered image are compared per
//    pixel by their estimated error (a filtered half against the other, independent half, less
//    that half's variance), smoothed over a neighbourhood; each pixel takes the candidate with
//    the least. Where no filter does better than the noise (a caustic no feature explains), the
//    pixel stays as rendered rather than smeared.
//
// A pure function of its input: the same buffers give the same image bit for bit at any thread
// count (each pixel is computed alone, in a fixed order of operations).
#pragma once

#include <cstddef>
#include <vector>

namespace veach {

// The denoiser's input: width x height, row 0 at the top, every buffer pixel-interleaved.
struct DenoiseInput {
    int width = 0, height = 0;
    // Two independent estimates of the image (3 floats per pixel each): even and odd samples.
    const float* half_a = nullptr;
    const float* half_b = nullptr;
    // The whole image (3 floats per pixel), returned where no filter helps; null: the halves'
    // average. With an odd number of samples the halves hold unequal counts and differ from it.
    const float* full = nullptr;
    // The variance of each half's pixel mean (3 floats per pixel), e.g. twice the whole image's
    // from its samples' sums of squares; null: estimated from the halves' difference, (A - B)^2
    // / 2 averaged over 3x3 pixels. Per pixel is better: a dark pixel beside a bright one is
    // judged by its own noise.
    const float* variance = nullptr;
    // The variance above leaves noise out (light-tracing splats, which no pixel's samples hold):
    // each pixel takes the larger of it and the halves' estimate.
    bool variance_is_partial = false;
    // Features, 3 floats per pixel each, averaged over all samples (either may be null: left
    // out of the regression). Where the camera sees a mirror or smooth glass, they describe the
    // first surface seen through it.
    const float* albedo = nullptr;
    const float* normal = nullptr;
    const float* position = nullptr;
};

struct DenoiseSettings {
    int window_radius = 6;  // the regression's window: (2r + 1)^2 pixels
    int patch_radius = 1;   // non-local means patches: (2r + 1)^2 pixels
    int error_radius = 4;   // the error estimates are averaged over (2r + 1)^2 pixels
};

struct DenoiseResult {
    std::vector<float> rgb;  // 3 floats per pixel: the denoised image
    // Which candidate each pixel took (0: unfiltered; higher: stronger filters), for diagnosis.
    std::vector<unsigned char> choice;
};

// Throws std::invalid_argument for a size that does not match (width or height < 1, missing
// halves). Non-finite input values are treated as 0.
DenoiseResult denoise(const DenoiseInput& input, const DenoiseSettings& settings = {});

// The bytes denoise() allocates for a width x height image (its memory bound).
size_t denoise_scratch_bytes(int width, int height);

}  // namespace veach
