// Where a process's cgroup limits live: its folder in each cgroup hierarchy and every folder
// above it, since a parent's limit bounds its children (a Slurm job step under its job, a systemd
// scope under a slice). Read by the default thread count (CPU quota) and the memory budgets.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

namespace veach {

// The process's path in one hierarchy, from the text of /proc/self/cgroup ("ID:CONTROLLERS:PATH"
// lines): the v2 line (ID 0, no controllers) when `controller` is empty, else the v1 line whose
// controllers include it. False when there is no such line.
bool cgroup_path(const std::string& self_cgroup, const std::string& controller, std::string* path);

// The folders to read, innermost first: the process's path and each of its ancestors up to the
// root, under each mount point in `mounts`. Inside a container the mount's root may be the
// container's own cgroup while the path names the host's; folders that do not exist read as no
// limit, so the walk up still reaches the root. A v2 walk (`controller` empty) without a v2 line
// is empty; a v1 walk without its controller's line reads the roots alone.
std::vector<std::string> cgroup_folders(const std::string& self_cgroup, const std::string& controller,
                                        std::initializer_list<std::string> mounts);

// The text of /proc/self/cgroup ("" where there is none).
std::string read_self_cgroup();

}  // namespace veach
