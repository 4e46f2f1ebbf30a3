// How much more memory this process can take before the system, its cgroup or its address-space
// limit refuses it: what a budget compares an allocation with before making it, so that a render
// too large for the machine is refused with a message instead of being OOM-killed silently.
#pragma once

#include <cstdint>
#include <string>

namespace veach {

// The smallest of: the kernel's MemAvailable, what the process's cgroups still allow
// (cgroup_memory_headroom) and RLIMIT_AS minus the address space in use. UINT64_MAX when none of
// them is known.
uint64_t available_memory_bytes();

// The smallest limit minus usage over the process's cgroup folders (its own and every parent's,
// core/cgroup_folders.h): memory.max - memory.current in the v2 hierarchy (at `sys_fs_cgroup` or
// its unified/ on hybrid systems), memory.limit_in_bytes - memory.usage_in_bytes in the v1 memory
// controller's (sys_fs_cgroup/memory). `self_cgroup` is the text of /proc/self/cgroup. UINT64_MAX
// when no folder sets a limit.
uint64_t cgroup_memory_headroom(const std::string& self_cgroup, const std::string& sys_fs_cgroup);

}  // namespace veach
