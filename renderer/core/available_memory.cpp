#include "core/available_memory.h"

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

// The folder of this process's cgroup under /sys/fs/cgroup (v2: the "0::" line).
std::string cgroup_folder() {
    std::ifstream f("/proc/self/cgroup");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("0::", 0) == 0) return "/sys/fs/cgroup" + line.substr(3);
    return "/sys/fs/cgroup";
}

}  // namespace

uint64_t available_memory_bytes() {
    uint64_t available = UINT64_MAX;
    if (uint64_t m = proc_kib("/proc/meminfo", "MemAvailable:"); m > 0) available = m;
    // cgroup v2, at this process's cgroup and (in a container) at the root of the namespace.
    for (const std::string& dir : {cgroup_folder(), std::string("/sys/fs/cgroup")}) {
        const uint64_t limit = read_number(dir + "/memory.max");
        if (limit > 0) available = std::min(available, limit - std::min(limit, read_number(dir + "/memory.current")));
    }
    // cgroup v1 (its "no limit" is a huge number, which the min ignores).
    if (uint64_t limit = read_number("/sys/fs/cgroup/memory/memory.limit_in_bytes"); limit > 0)
        available =
            std::min(available, limit - std::min(limit, read_number("/sys/fs/cgroup/memory/memory.usage_in_bytes")));
    rlimit as{};
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
        const uint64_t used = proc_kib("/proc/self/status", "VmSize:");
        available = std::min<uint64_t>(available, as.rlim_cur - std::min<uint64_t>(as.rlim_cur, used));
    }
    return available;
}

}  // namespace veach
