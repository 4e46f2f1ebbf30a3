// Part files (.vpart): one piece of a render split across machines, by sample range, by pixel
// rectangle or both, and the merge that sums pieces into the image one machine would have made.
//
// Why this is exact: randomness is keyed by (seed, pixel, sample index), so a sample is the same
// whichever machine takes it, and the film keeps double sums, so adding the parts' sums in
// sample order gives the single render's sums (and its float image bit for bit for camera
// samples; splats land from many threads in any order, so those agree to summation order). A
// merge of float images would round every part first.
//
// The file: magic "VEACHPRT", a text header (the identity hash, the version of veach that wrote
// it, size, sample range, bounds, frame and the settings the image's metadata names), the film's sums for the part's pixels and
// its splats for the whole frame as doubles (each block of doubles byte-shuffled, then zlib), a
// CRC-32 of everything before it and an end marker. Written through AtomicFile: never torn.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "film/film.h"

namespace veach {

// A part file that cannot be used: unreadable, corrupt, or not mergeable with the others
// (front ends: bad input, exit 2). The message is one line naming the files.
class PartError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct PartInfo {
    uint64_t identity = 0;  // every image-shaping setting and the content of every input file
    // The veach that rendered it ("0.6.0"; empty in parts from before it was recorded): parts of
    // two versions never merge, since sampling may differ between them.
    std::string version;
    int width = 0, height = 0;
    bool aovs = false;
    int sample_begin = 0, sample_end = 0;  // sample indices [begin, end) of every pixel in bounds
    int spp = 0;                           // the samples per pixel of the whole render
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;    // pixels [x0, x1) x [y0, y1)
    double frame = 0;
    // What the image's metadata says about the render.
    uint64_t seed = 0;
    std::string camera, integrator, scene;
    FilterSettings filter;
    double render_seconds = 0;

    uint64_t area() const { return static_cast<uint64_t>(x1 - x0) * static_cast<uint64_t>(y1 - y0); }
    // Camera samples the part holds (or would, none dropped): its range times its area.
    uint64_t sample_pixels() const { return static_cast<uint64_t>(sample_end - sample_begin) * area(); }
};

// Writes the film's sums for info's bounds, and its splats, to `path`. Throws OutputError.
void write_film_part(const std::string& path, const Film& film, const PartInfo& info);

// Reads only the header (cheap: to check a set of parts before loading any). Throws PartError.
PartInfo read_film_part_info(const std::string& path);

// The result of merging parts: a film holding the summed sums, and what the image says.
struct MergedParts {
    PartInfo info;  // the first part's settings; sample range and bounds of the whole when it is
                    // one range over one rectangle (see single_piece)
    std::shared_ptr<Film> film;
    // Splats are divided by this: the light paths traced per pixel of the frame (every camera
    // sample traces one), i.e. the parts' camera samples over the frame's pixels.
    double splat_spp = 0;
    int min_spp = 0;            // the samples every pixel of the frame holds
    bool single_piece = false;  // the parts form one sample range over one rectangle
    std::vector<std::string> paths;
};

// Sums the parts. Refuses (PartError, one line naming the files) parts made by two versions of
// veach (naming both), parts of different renders (identity, size, passes or frame differ), parts overlapping in samples and pixels, a corrupt
// part, and, when expect_spp > 0, parts that do not cover samples [0, expect_spp) of every
// pixel exactly.
MergedParts merge_film_parts(const std::vector<std::string>& paths, int expect_spp);

}  // namespace veach
