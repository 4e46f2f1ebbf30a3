// Files replaced atomically: every file Veach writes (images, checkpoints, part files, the
// command's --stats-json) goes through AtomicFile, so that a full disk, a failed write or a
// killed process leaves either the old file or the complete new one under the final name, never
// a torn one.
//
// The protocol: a temporary file is created beside the target with O_CREAT | O_EXCL |
// O_NOFOLLOW and a random name (mkstemp's rule: nobody can plant a symlink or file there that we
// would write through), every write and the close are checked, the data is fsync'ed, and only
// then is the temporary renamed over the target (atomic within one folder) and the folder
// fsync'ed. Any failure removes the temporary file and throws OutputError naming the target.
//
// A target that already exists as a character device or FIFO (/dev/stdout, /dev/null, a pipe)
// cannot be replaced by renaming: it is written in place, every write still checked, so
// `--stats-json /dev/full` fails as it should. A FIFO without a reader is refused rather than
// blocking. A folder, or any other kind of file, is refused.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace veach {

// A file that could not be written: one line naming it and the reason. Front ends map it to
// exit code 3 (a failure of the machine, not of the input).
class OutputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class AtomicFile {
public:
    // Creates the temporary file beside `path` (or opens the device or FIFO). Throws OutputError.
    explicit AtomicFile(const std::string& path);
    // Removes the temporary file unless commit() succeeded.
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    // Appends `size` bytes; a short or failed write throws OutputError (and discards the file).
    void write(const void* data, size_t size);
    // fsync, close, rename onto the target, fsync the folder. Throws OutputError on failure.
    void commit();

    const std::string& path() const { return m_path; }

private:
    [[noreturn]] void fail(const std::string& what, int error);
    void discard() noexcept;

    std::string m_path;  // the target
    std::string m_temp;  // the temporary file; empty when writing a device or FIFO in place
    int m_fd = -1;
    bool m_committed = false;
};

// One buffer written through AtomicFile.
void write_file_atomically(const std::string& path, const void* data, size_t size);

// Throws the OutputError that AtomicFile(path) would, without writing anything: the folder
// exists and a temporary file can really be created in it (created and removed again, since
// permission bits say nothing for root and nothing about a read-only mount), and the target is
// not a folder or other unwritable kind. A device or FIFO target passes (a FIFO's reader may
// come later). For checking a render's outputs before spending the render's time.
void check_writable(const std::string& path);

}  // namespace veach
