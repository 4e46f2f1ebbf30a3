#include "output/atomic_file.h"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <optional>

namespace veach {

namespace {

// The folder part of `path` ("." for a bare name) and its last component.
struct PathParts {
    std::string folder, name;
};
PathParts split_path(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return {std::string("."), path};
    return {slash == 0 ? std::string(1, '/') : path.substr(0, slash), path.substr(slash + 1)};
}

// Eight characters from [a-z0-9], from the kernel's generator (unpredictable, unlike a pid or a
// counter, so nobody can create the name before us; O_EXCL refuses it if they do anyway).
std::string random_suffix() {
    static constexpr char k_alphabet[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    uint8_t bytes[8] = {};
    size_t got = 0;
    while (got < sizeof(bytes)) {
        const ssize_t n = ::getrandom(bytes + got, sizeof(bytes) - got, 0);
        if (n > 0)
            got += static_cast<size_t>(n);
        else if (errno != EINTR)
            break;  // no randomness: the names below still differ by their position, and O_EXCL holds
    }
    std::string s(8, 'x');
    for (size_t i = 0; i < sizeof(bytes); ++i) s[i] = k_alphabet[bytes[i] % (sizeof(k_alphabet) - 1)];
    return s;
}

}  // namespace

AtomicFile::AtomicFile(const std::string& path) : m_path(path) {
    if (path.empty()) throw OutputError("cannot write a file with an empty name");
    const auto [folder, name] = split_path(path);
    if (name.empty()) fail("is a folder", EISDIR);

    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) fail("is a folder", EISDIR);
        if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
            // Written in place. O_NONBLOCK so that a FIFO nobody reads fails (ENXIO) instead of
            // blocking the render forever; writes then block as usual.
            m_fd = ::open(path.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC | O_NONBLOCK);
            if (m_fd < 0) fail("cannot open", errno);
            const int flags = ::fcntl(m_fd, F_GETFL);
            if (flags < 0 || ::fcntl(m_fd, F_SETFL, flags & ~O_NONBLOCK) < 0) fail("cannot open", errno);
            return;
        }
        if (!S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode)) fail("is not a regular file", EINVAL);
        // A symlink at the target is replaced by the rename, never written through.
    }
    struct stat fst {};
    if (::stat(folder.c_str(), &fst) != 0) fail("cannot write into folder '" + folder + "'", errno);
    if (!S_ISDIR(fst.st_mode)) fail("'" + folder + "' is not a folder", ENOTDIR);

    // ".NAME.tmp-XXXXXXXX": the leading dot keeps half-written files out of casual listings.
    for (int attempt = 0; attempt < 64; ++attempt) {
        std::string temp = folder + "/." + name + ".tmp-" + random_suffix();
        m_fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY, 0666);
        if (m_fd >= 0) {
            m_temp = std::move(temp);
            return;
        }
        if (errno != EEXIST) fail("cannot create a temporary file in '" + folder + "'", errno);
    }
    fail("cannot create a temporary file in '" + folder + "'", EEXIST);
}

AtomicFile::~AtomicFile() {
    if (!m_committed) discard();
}

void AtomicFile::discard() noexcept {
    if (m_fd >= 0) ::close(m_fd);
    m_fd = -1;
    if (!m_temp.empty()) ::unlink(m_temp.c_str());
    m_temp.clear();
}

void AtomicFile::fail(const std::string& what, int error) {
    discard();
    throw OutputError(m_path + ": " + what + " (" + std::strerror(error) + ")");
}

namespace {

// Writing to a FIFO whose reader has gone raises SIGPIPE, whose default action would kill a host
// process that never asked for it: the signal is blocked on this thread around the write (which
// then fails with EPIPE, reported as an error), and the one it raised is consumed.
class SigpipeBlocked {
public:
    SigpipeBlocked() {
        sigemptyset(&m_pipe);
        sigaddset(&m_pipe, SIGPIPE);
        sigset_t pending;
        m_was_pending = sigpending(&pending) == 0 && sigismember(&pending, SIGPIPE) == 1;
        pthread_sigmask(SIG_BLOCK, &m_pipe, &m_old);
    }
    ~SigpipeBlocked() {
        if (!m_was_pending) {
            const timespec zero{0, 0};
            while (sigtimedwait(&m_pipe, nullptr, &zero) == SIGPIPE) {}
        }
        pthread_sigmask(SIG_SETMASK, &m_old, nullptr);
    }

private:
    sigset_t m_pipe, m_old;
    bool m_was_pending = false;
};

}  // namespace

void AtomicFile::write(const void* data, size_t size) {
    if (m_fd < 0) throw OutputError(m_path + ": write after the file was closed");
    const auto* p = static_cast<const unsigned char*>(data);
    int error = 0;
    {
        std::optional<SigpipeBlocked> blocked;
        if (m_temp.empty()) blocked.emplace();  // a device or FIFO, written in place
        while (size > 0) {
            const ssize_t n = ::write(m_fd, p, size);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                error = n < 0 ? errno : EIO;
                break;
            }
            p += n;
            size -= static_cast<size_t>(n);
        }
    }
    if (error != 0) fail("write failed", error);
}

void AtomicFile::commit() {
    if (m_fd < 0) throw OutputError(m_path + ": commit after the file was closed");
    if (m_temp.empty()) {
        // A device or FIFO: nothing to rename; close() may still report a deferred error.
        const int fd = m_fd;
        m_fd = -1;
        if (::close(fd) != 0 && errno != EINTR) fail("write failed", errno);
        m_committed = true;
        return;
    }
    // The data must be on disk before the name points at it, or a crash right after the rename
    // could leave the final name on an empty file.
    if (::fsync(m_fd) != 0) fail("write failed", errno);
    const int fd = m_fd;
    m_fd = -1;
    if (::close(fd) != 0 && errno != EINTR) fail("write failed", errno);
    if (::rename(m_temp.c_str(), m_path.c_str()) != 0) fail("cannot replace the file", errno);
    m_temp.clear();
    m_committed = true;
    // The rename itself is durable once the folder is: best effort, the file is complete either way.
    const int dir = ::open(split_path(m_path).folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
}

void write_file_atomically(const std::string& path, const void* data, size_t size) {
    AtomicFile file(path);
    file.write(data, size);
    file.commit();
}

void check_writable(const std::string& path) {
    struct stat st {};
    if (!path.empty() && ::lstat(path.c_str(), &st) == 0 && (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode))) return;
    AtomicFile probe(path);  // never committed: its destructor removes the temporary file
}

}  // namespace veach
