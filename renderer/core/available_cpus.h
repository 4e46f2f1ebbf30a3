// The CPUs this process may use, as a farm task sees them: the affinity mask (taskset, Slurm's
// and Kubernetes' CPU binding) and the cgroup CPU quota (cpu.max in cgroup v2, cfs_quota_us in
// v1), not the machine's core count, so that the default thread count never oversubscribes a
// share of a node.
#pragma once

namespace veach {

// At least 1.
int available_cpus();

}  // namespace veach
