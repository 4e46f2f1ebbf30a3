// Durability of every file Veach writes: the data is fsync'ed before the temporary file is renamed
// over the target (and the folder after), so a node that crashes or loses power right after the
// rename never leaves a complete-looking name on an empty or partial file.
//
// The order is observed, not assumed: this test executable defines fsync() and rename(), which
// take precedence over libc's for every caller in the process (the renderer is linked in
// statically), records each call while a test listens, and forwards to libc's own.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <stdio.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "film/film.h"
#include "output/atomic_file.h"
#include "output/image_output.h"

namespace {

struct Event {
    std::string what, path, to;  // "fsync" PATH, or "rename" PATH -> TO
};
std::atomic<bool> g_listening{false};
std::mutex g_mutex;
std::vector<Event> g_events;

std::string path_of_fd(int fd) {
    char buf[4096];
    const std::string link = "/proc/self/fd/" + std::to_string(fd);
    const ssize_t n = ::readlink(link.c_str(), buf, sizeof(buf) - 1);
    return n > 0 ? std::string(buf, static_cast<size_t>(n)) : std::string();
}

void record(Event e) {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_events.push_back(std::move(e));
}

}  // namespace

extern "C" int fsync(int fd) {
    using Fn = int (*)(int);
    static Fn real = reinterpret_cast<Fn>(::dlsym(RTLD_NEXT, "fsync"));
    if (g_listening.load()) record({"fsync", path_of_fd(fd), {}});
    return real(fd);
}

extern "C" int rename(const char* from, const char* to) {
    using Fn = int (*)(const char*, const char*);
    static Fn real = reinterpret_cast<Fn>(::dlsym(RTLD_NEXT, "rename"));
    if (g_listening.load())
        record({"rename", std::filesystem::absolute(from).lexically_normal().string(),
                std::filesystem::absolute(to).lexically_normal().string()});
    return real(from, to);
}

namespace veach {
namespace {

namespace fs = std::filesystem;

class DurableWrite : public ::testing::Test {
protected:
    void SetUp() override {
        // Canonical: /proc/self/fd names the real path, symlinks in the temp path resolved.
        m_dir = fs::canonical(fs::temp_directory_path()) / ("veach_durable_" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
        std::lock_guard<std::mutex> lock(g_mutex);
        g_events.clear();
    }
    void TearDown() override {
        g_listening = false;
        fs::remove_all(m_dir);
    }
    static std::vector<Event> events() {
        std::lock_guard<std::mutex> lock(g_mutex);
        return g_events;
    }
    // The rename onto `target` was preceded by an fsync of the very file renamed, and followed
    // by an fsync of the folder.
    static void expect_synced_before_rename(const std::vector<Event>& ev, const fs::path& target) {
        int rename_at = -1;
        for (size_t i = 0; i < ev.size(); ++i)
            if (ev[i].what == "rename" && ev[i].to == target.string()) rename_at = static_cast<int>(i);
        ASSERT_GE(rename_at, 0) << "no rename onto " << target;
        const std::string temp = ev[rename_at].path;
        EXPECT_NE(temp, target.string());
        bool data_synced = false;
        for (int i = 0; i < rename_at; ++i) data_synced = data_synced || (ev[i].what == "fsync" && ev[i].path == temp);
        EXPECT_TRUE(data_synced) << "the data of " << temp << " was not fsync'ed before the rename";
        bool folder_synced = false;
        for (size_t i = rename_at + 1; i < ev.size(); ++i)
            folder_synced = folder_synced || (ev[i].what == "fsync" && ev[i].path == target.parent_path().string());
        EXPECT_TRUE(folder_synced) << "the folder was not fsync'ed after the rename";
    }

    fs::path m_dir;
};

TEST_F(DurableWrite, AtomicFileSyncsTheDataBeforeTheRename) {
    const fs::path target = m_dir / "stats.json";
    g_listening = true;
    write_file_atomically(target.string(), "{}\n", 3);
    g_listening = false;
    expect_synced_before_rename(events(), target);
}

TEST_F(DurableWrite, ImagesGoThroughTheSameSyncedRename) {
    Image image;
    image.width = 4;
    image.height = 2;
    image.rgba.assign(4 * 2 * 4, 0.5f);
    for (const char* name : {"a.exr", "a.png"}) {
        const fs::path target = m_dir / name;
        {
            std::lock_guard<std::mutex> lock(g_mutex);
            g_events.clear();
        }
        g_listening = true;
        write_image(image, target.string(), OutputSettings{});
        g_listening = false;
        expect_synced_before_rename(events(), target);
    }
}

}  // namespace
}  // namespace veach
