// Resumable render state: the film's sums, the samples per pixel completed and a hash of every
// setting that shapes the image, in one binary file written through AtomicFile
// (output/atomic_file.h), so that a killed process or a full disk leaves either the previous
// checkpoint or the new one, never a torn file.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/content_hash.h"
#include "film/film.h"

namespace veach {

// A checkpoint that cannot be used (bad input for a front end)...
class CheckpointError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};
// ...or cannot be written (a failure of the machine: disk full, no permission).
class CheckpointWriteError : public CheckpointError {
public:
    using CheckpointError::CheckpointError;
};

// Writes the film (only while no thread renders into it). Throws CheckpointWriteError naming
// the file.
void write_film_checkpoint(const std::string& path, const Film& film, uint64_t settings_hash, int spp_done);

// Loads a checkpoint written for the same film size, AOV set and settings hash into `film`;
// returns its spp. Throws CheckpointError with a one-line message naming the file and the fault
// (unreadable, truncated, not a checkpoint, made with other settings).
int read_film_checkpoint(const std::string& path, Film& film, uint64_t settings_hash);

}  // namespace veach
