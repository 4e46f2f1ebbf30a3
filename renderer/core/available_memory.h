// How much more memory this process can take before the system, its cgroup or its address-space
// limit refuses it: what a budget compares an allocation with before making it, so that a render
// too large for the machine is refused with a message instead of being OOM-killed silently.
#pragma once

#include <cstdint>

namespace veach {

// The smallest of: the kernel's MemAvailable, the cgroup's memory.max minus memory.current (v2,
// or v1's limit_in_bytes minus usage_in_bytes), and RLIMIT_AS minus the address space in use.
// UINT64_MAX when none of them is known.
uint64_t available_memory_bytes();

}  // namespace veach
