#include "core/available_cpus.h"

#include <sched.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace veach {

namespace {

// CPUs a quota allows: ceil(quota / period); 0 when there is none.
int quota_cpus(double quota, double period) {
    if (!(quota > 0) || !(period > 0)) return 0;
    return std::max(1, static_cast<int>(std::ceil(quota / period)));
}

// cgroup v2: the tightest cpu.max from the process's cgroup up to the root of the hierarchy
// (a parent's quota bounds its children). The unified hierarchy is at /sys/fs/cgroup, or at
// /sys/fs/cgroup/unified on hybrid systems.
int cgroup_v2_cpus() {
    std::ifstream self("/proc/self/cgroup");
    std::string line, path;
    bool found = false;
    while (std::getline(self, line))
        if (line.rfind("0::", 0) == 0) path = line.substr(3), found = true;
    if (!found) return 0;
    int best = 0;
    for (const char* root : {"/sys/fs/cgroup", "/sys/fs/cgroup/unified"}) {
        for (std::string p = path;;) {
            std::ifstream f(std::string(root) + (p == "/" ? "" : p) + "/cpu.max");
            std::string text;
            if (std::getline(f, text)) {
                const int n = cpus_from_cpu_max(text);
                if (n > 0) best = best > 0 ? std::min(best, n) : n;
            }
            if (p.empty() || p == "/") break;
            const size_t slash = p.find_last_of('/');
            p = slash == std::string::npos || slash == 0 ? std::string("/") : p.substr(0, slash);
        }
    }
    return best;
}

int cgroup_v1_cpus() {
    std::ifstream q("/sys/fs/cgroup/cpu/cpu.cfs_quota_us"), p("/sys/fs/cgroup/cpu/cpu.cfs_period_us");
    double quota = 0, period = 0;
    if (q >> quota && p >> period) return quota_cpus(quota, period);
    return 0;
}

}  // namespace

int cpus_from_cpu_max(const std::string& line) {
    std::istringstream in(line);
    std::string quota;
    double period = 0;
    if (!(in >> quota >> period) || quota == "max") return 0;
    char* end = nullptr;
    const double q = std::strtod(quota.c_str(), &end);
    if (end == quota.c_str() || *end != '\0') return 0;
    return quota_cpus(q, period);
}

int available_cpus() {
    int n = 0;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof(set), &set) == 0) n = CPU_COUNT(&set);
    if (n <= 0) n = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    int quota = cgroup_v2_cpus();
    if (quota == 0) quota = cgroup_v1_cpus();
    if (quota > 0) n = std::min(n, quota);
    return std::max(1, n);
}

}  // namespace veach
