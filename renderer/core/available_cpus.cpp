#include "core/available_cpus.h"

#include <sched.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
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

// The process's path in a cgroup hierarchy, from /proc/self/cgroup ("ID:CONTROLLERS:PATH"):
// the v2 line (ID 0, no controllers) or the v1 line whose controllers include `controller`.
bool cgroup_path(const std::string& controller, std::string* path) {
    std::ifstream self("/proc/self/cgroup");
    std::string line;
    while (std::getline(self, line)) {
        const size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos) continue;
        const std::string controllers = "," + line.substr(a + 1, b - a - 1) + ",";
        if (controller.empty() ? line.compare(0, 3, "0::") == 0
                               : controllers.find("," + controller + ",") != std::string::npos) {
            *path = line.substr(b + 1);
            return true;
        }
    }
    return false;
}

// The tightest quota (`cpus_in(folder)`, 0 for none) from the process's cgroup folder up to the
// root of the hierarchy, under each place it may be mounted: a parent's quota bounds its
// children. Inside a container the hierarchy's root may be the container's own cgroup while
// /proc/self/cgroup names the host's path; folders that do not exist are simply passed by, so
// the walk up reaches the mount's root either way.
template <class CpusIn>
int tightest_quota(const std::string& path, std::initializer_list<const char*> mounts, CpusIn&& cpus_in) {
    int best = 0;
    for (const char* root : mounts) {
        for (std::string p = path;;) {
            const int n = cpus_in(std::string(root) + (p == "/" ? "" : p));
            if (n > 0) best = best > 0 ? std::min(best, n) : n;
            if (p.empty() || p == "/") break;
            const size_t slash = p.find_last_of('/');
            p = slash == std::string::npos || slash == 0 ? std::string("/") : p.substr(0, slash);
        }
    }
    return best;
}

// cgroup v2: cpu.max. The unified hierarchy is at /sys/fs/cgroup, or at /sys/fs/cgroup/unified
// on hybrid systems.
int cgroup_v2_cpus() {
    std::string path;
    if (!cgroup_path("", &path)) return 0;
    return tightest_quota(path, {"/sys/fs/cgroup", "/sys/fs/cgroup/unified"}, [](const std::string& folder) {
        std::ifstream f(folder + "/cpu.max");
        std::string text;
        return std::getline(f, text) ? cpus_from_cpu_max(text) : 0;
    });
}

// cgroup v1: cpu.cfs_quota_us over cpu.cfs_period_us (-1: none) in the cpu controller's
// hierarchy, mounted as cpu or as cpu,cpuacct.
int cgroup_v1_cpus() {
    std::string path;
    if (!cgroup_path("cpu", &path)) path = "/";
    return tightest_quota(path, {"/sys/fs/cgroup/cpu", "/sys/fs/cgroup/cpu,cpuacct"}, [](const std::string& folder) {
        std::ifstream q(folder + "/cpu.cfs_quota_us"), p(folder + "/cpu.cfs_period_us");
        double quota = 0, period = 0;
        return q >> quota && p >> period ? quota_cpus(quota, period) : 0;
    });
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
