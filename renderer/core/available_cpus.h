// The CPUs this process may use, as a farm task sees them: the affinity mask (taskset, Slurm's
// and Kubernetes' CPU binding) and the cgroup CPU quota (cpu.max in cgroup v2, cfs_quota_us in
// v1), not the machine's core count, so that the default thread count never oversubscribes a
// share of a node.
#pragma once

#include <string>

namespace veach {

// At least 1: the affinity mask's CPUs, lowered to the tightest cgroup quota (rounded up).
int available_cpus();

// CPUs a cgroup v2 cpu.max line allows ("QUOTA PERIOD" in microseconds: ceil(QUOTA / PERIOD),
// at least 1); 0 for "max ..." (no quota) or a line that does not parse.
int cpus_from_cpu_max(const std::string& line);

}  // namespace veach
