// The default thread count: the CPUs the process may use, never more than its affinity mask
// allows, and a cgroup v2 quota read as the kernel writes it ("QUOTA PERIOD" or "max PERIOD").
#include <gtest/gtest.h>
#include <sched.h>

#include "core/available_cpus.h"

namespace veach {
namespace {

TEST(AvailableCpus, CpuMaxQuotaRoundsUpAndMaxMeansNone) {
    EXPECT_EQ(cpus_from_cpu_max("max 100000"), 0);
    EXPECT_EQ(cpus_from_cpu_max("100000 100000"), 1);
    EXPECT_EQ(cpus_from_cpu_max("150000 100000"), 2);  // one and a half CPUs: two threads
    EXPECT_EQ(cpus_from_cpu_max("50000 100000"), 1);   // half a CPU still needs a thread
    EXPECT_EQ(cpus_from_cpu_max("400000 100000\n"), 4);
    EXPECT_EQ(cpus_from_cpu_max(""), 0);
    EXPECT_EQ(cpus_from_cpu_max("garbage"), 0);
    EXPECT_EQ(cpus_from_cpu_max("100000 0"), 0);
}

TEST(AvailableCpus, NeverMoreThanTheAffinityMask) {
    cpu_set_t set;
    CPU_ZERO(&set);
    ASSERT_EQ(sched_getaffinity(0, sizeof(set), &set), 0);
    const int allowed = CPU_COUNT(&set);
    const int n = available_cpus();
    EXPECT_GE(n, 1);
    EXPECT_LE(n, allowed);
    // Narrowed to one CPU (what taskset -c does), the answer follows; then restored.
    cpu_set_t one;
    CPU_ZERO(&one);
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &set)) {
            CPU_SET(c, &one);
            break;
        }
    ASSERT_EQ(sched_setaffinity(0, sizeof(one), &one), 0);
    EXPECT_EQ(available_cpus(), 1);
    ASSERT_EQ(sched_setaffinity(0, sizeof(set), &set), 0);
}

}  // namespace
}  // namespace veach
