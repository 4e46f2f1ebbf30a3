#include "core/available_memory.h"

#include "core/cgroup_folders.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

namespace veach {

namespace {

// The first number in `path`, or 0 when it is missing or not a number ("max").
uint64_t read_number(const std::string& path) {
    std::ifstream f(path);
    uint64_t v = 0;
    if (!(f >> v)) return 0;
    return v;
}

// A "Key:   N kB" line of a /proc file, in bytes; 0 when absent.
uint64_t proc_kib(const char* path, const std::string& key) {
    std::ifstream f(path);
    std::string line;
    while (std::getline(f, line))
        if (line.rfind(key, 0) == 0) return std::strtoull(line.c_str() + key.size(), nullptr, 10) * 1024;
    return 0;
}

}  // namespace

uint64_t cgroup_memory_headroom(const std::string& self_cgroup, const std::string& sys_fs_cgroup) {
    uint64_t headroom = UINT64_MAX;
    auto bound = [&](const std::string& limit_file, const std::string& usage_file) {
        // "max" (v2) reads as 0: no limit there; v1's "no limit" is a huge number, which the min ignores.
        if (const uint64_t limit = read_number(limit_file); limit > 0)
            headroom = std::min(headroom, limit - std::min(limit, read_number(usage_file)));
    };
    for (const std::string& folder : cgroup_folders(self_cgroup, "", {sys_fs_cgroup, sys_fs_cgroup + "/unified"}))
        bound(folder + "/memory.max", folder + "/memory.current");
    for (const std::string& folder : cgroup_folders(self_cgroup, "memory", {sys_fs_cgroup + "/memory"}))
        bound(folder + "/memory.limit_in_bytes", folder + "/memory.usage_in_bytes");
    return headroom;
}

uint64_t available_memory_bytes() {
    uint64_t available = UINT64_MAX;
    if (uint64_t m = proc_kib("/proc/meminfo", "MemAvailable:"); m > 0) available = m;
    available = std::min(available, cgroup_memory_headroom(read_self_cgroup(), "/sys/fs/cgroup"));
    rlimit as{};
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
        const uint64_t used = proc_kib("/proc/self/status", "VmSize:");
        available = std::min<uint64_t>(available, as.rlim_cur - std::min<uint64_t>(as.rlim_cur, used));
    }
    return available;
}

}  // namespace veach
