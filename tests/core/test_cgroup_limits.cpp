// The cgroup limits a process lives under: its own cgroup folder and every parent's, in the v2
// hierarchy (at /sys/fs/cgroup, or unified/ on hybrid systems) and in v1's controllers. A farm
// puts a job step below its job (Slurm: /slurm/uid_0/job_7/step_0, the limit on job_7); a
// systemd scope sits below the slice with MemoryMax. The memory headroom is read here from a
// folder tree laid out like /sys/fs/cgroup.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/available_memory.h"
#include "core/cgroup_folders.h"

namespace veach {
namespace {

constexpr uint64_t k_mib = 1 << 20;
constexpr const char* k_v1_unlimited = "9223372036854771712";  // what the kernel writes for no limit

class CgroupTree : public ::testing::Test {
protected:
    void SetUp() override {
        m_root = std::filesystem::temp_directory_path() / ("veach_cgroup_tree_" + std::to_string(::getpid()));
        std::filesystem::remove_all(m_root);
    }
    void TearDown() override { std::filesystem::remove_all(m_root); }
    void write(const std::string& relative, const std::string& text) {
        const std::filesystem::path p = m_root / relative;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p) << text << "\n";
    }
    std::string root() const { return m_root.string(); }
    std::filesystem::path m_root;
};

TEST(CgroupFolders, OwnFolderThenEachParentUnderEachMount) {
    const std::string self = "4:memory:/a/b\n1:cpu,cpuacct:/c\n0::/u/v\n";
    EXPECT_EQ(cgroup_folders(self, "memory", {"/m"}), (std::vector<std::string>{"/m/a/b", "/m/a", "/m"}));
    EXPECT_EQ(cgroup_folders(self, "cpu", {"/x", "/y"}), (std::vector<std::string>{"/x/c", "/x", "/y/c", "/y"}));
    EXPECT_EQ(cgroup_folders(self, "", {"/s", "/s/unified"}),
              (std::vector<std::string>{"/s/u/v", "/s/u", "/s", "/s/unified/u/v", "/s/unified/u", "/s/unified"}));
    // No v2 line: no v2 folders; no line for a v1 controller: its roots alone.
    EXPECT_TRUE(cgroup_folders("4:memory:/a\n", "", {"/s"}).empty());
    EXPECT_EQ(cgroup_folders("0::/\n", "memory", {"/m"}), (std::vector<std::string>{"/m"}));
}

TEST_F(CgroupTree, V1LimitOnAParentBoundsAJobStep) {
    const std::string self = "9:name=systemd:/\n4:memory:/slurm/uid_0/job_7/step_0\n0::/\n";
    write("memory/memory.limit_in_bytes", k_v1_unlimited);
    write("memory/slurm/uid_0/job_7/step_0/memory.limit_in_bytes", k_v1_unlimited);
    write("memory/slurm/uid_0/job_7/step_0/memory.usage_in_bytes", std::to_string(100 * k_mib));
    write("memory/slurm/uid_0/job_7/memory.limit_in_bytes", std::to_string(1024 * k_mib));
    write("memory/slurm/uid_0/job_7/memory.usage_in_bytes", std::to_string(256 * k_mib));
    EXPECT_EQ(cgroup_memory_headroom(self, root()), 768 * k_mib);
    // The step's own, tighter limit wins over the job's.
    write("memory/slurm/uid_0/job_7/step_0/memory.limit_in_bytes", std::to_string(300 * k_mib));
    EXPECT_EQ(cgroup_memory_headroom(self, root()), 200 * k_mib);
}

TEST_F(CgroupTree, V2SliceLimitBoundsTheScopeBelowIt) {
    const std::string self = "0::/user.slice/user-0.slice/session-1.scope\n";
    write("user.slice/user-0.slice/session-1.scope/memory.max", "max");
    write("user.slice/user-0.slice/session-1.scope/memory.current", std::to_string(10 * k_mib));
    write("user.slice/memory.max", std::to_string(2048 * k_mib));
    write("user.slice/memory.current", std::to_string(512 * k_mib));
    EXPECT_EQ(cgroup_memory_headroom(self, root()), 1536 * k_mib);
}

TEST_F(CgroupTree, V2OnAHybridSystemIsReadUnderUnified) {
    const std::string self = "4:memory:/\n0::/job\n";
    write("memory/memory.limit_in_bytes", k_v1_unlimited);
    write("unified/job/memory.max", std::to_string(64 * k_mib));
    write("unified/job/memory.current", std::to_string(16 * k_mib));
    EXPECT_EQ(cgroup_memory_headroom(self, root()), 48 * k_mib);
}

TEST_F(CgroupTree, AContainersOwnRootLimitIsFoundWhenTheHostPathIsAbsent) {
    // Docker on v1 mounts the container's cgroup as the root while /proc/self/cgroup names the
    // host's path, which does not exist inside.
    const std::string self = "4:memory:/docker/0123abcd\n0::/\n";
    write("memory/memory.limit_in_bytes", std::to_string(512 * k_mib));
    write("memory/memory.usage_in_bytes", std::to_string(128 * k_mib));
    EXPECT_EQ(cgroup_memory_headroom(self, root()), 384 * k_mib);
}

TEST_F(CgroupTree, NoLimitAnywhereIsNoBoundAndUsageOverTheLimitIsNoRoom) {
    const std::string self = "4:memory:/a\n0::/a\n";
    write("memory/a/memory.limit_in_bytes", k_v1_unlimited);
    write("a/memory.max", "max");
    EXPECT_GE(cgroup_memory_headroom(self, root()), uint64_t(1) << 62);  // v1's "no limit" bounds nothing
    write("a/memory.max", std::to_string(8 * k_mib));
    write("a/memory.current", std::to_string(9 * k_mib));
    EXPECT_EQ(cgroup_memory_headroom(self, root()), 0u);
    EXPECT_EQ(cgroup_memory_headroom("", root()), UINT64_MAX);
}

}  // namespace
}  // namespace veach
