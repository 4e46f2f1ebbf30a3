#include "core/available_cpus.h"

#include "core/cgroup_folders.h"

#include <sched.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace veach {

namespace {

// CPUs a quota allows: ceil(quota / period); 0 when there is none.
int quota_cpus(double quota, double period) {
    if (!(quota > 0) || !(period > 0)) return 0;
    return std::max(1, static_cast<int>(std::ceil(quota / period)));
}

// The tightest quota (`cpus_in(folder)`, 0 for none) over the process's cgroup folders: its own
// and every parent's, under each place the hierarchy may be mounted.
template <class CpusIn>
int tightest_quota(const std::vector<std::string>& folders, CpusIn&& cpus_in) {
    int best = 0;
    for (const std::string& folder : folders) {
        const int n = cpus_in(folder);
        if (n > 0) best = best > 0 ? std::min(best, n) : n;
    }
    return best;
}

// cgroup v2: cpu.max. The unified hierarchy is at /sys/fs/cgroup, or at /sys/fs/cgroup/unified
// on hybrid systems.
int cgroup_v2_cpus(const std::string& self) {
    auto cpus_in = [](const std::string& folder) {
        std::ifstream f(folder + "/cpu.max");
        std::string text;
        return std::getline(f, text) ? cpus_from_cpu_max(text) : 0;
    };
    return tightest_quota(cgroup_folders(self, "", {"/sys/fs/cgroup", "/sys/fs/cgroup/unified"}), cpus_in);
}

// cgroup v1: cpu.cfs_quota_us over cpu.cfs_period_us (-1: none) in the cpu controller's
// hierarchy, mounted as cpu or as cpu,cpuacct.
int cgroup_v1_cpus(const std::string& self) {
    auto cpus_in = [](const std::string& folder) {
        std::ifstream q(folder + "/cpu.cfs_quota_us"), p(folder + "/cpu.cfs_period_us");
        double quota = 0, period = 0;
        return q >> quota && p >> period ? quota_cpus(quota, period) : 0;
    };
    return tightest_quota(cgroup_folders(self, "cpu", {"/sys/fs/cgroup/cpu", "/sys/fs/cgroup/cpu,cpuacct"}), cpus_in);
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
    const std::string self = read_self_cgroup();
    int quota = cgroup_v2_cpus(self);
    if (quota == 0) quota = cgroup_v1_cpus(self);
    if (quota > 0) n = std::min(n, quota);
    return std::max(1, n);
}

}  // namespace veach
