#include "core/cgroup_folders.h"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace veach {

bool cgroup_path(const std::string& self_cgroup, const std::string& controller, std::string* path) {
    std::istringstream self(self_cgroup);
    std::string line;
    while (std::getline(self, line)) {
        const size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos) continue;
        bool match = controller.empty() && line.compare(0, 3, "0::") == 0;
        for (size_t c = a + 1; !controller.empty() && !match && c <= b;) {  // one of "cpu,cpuacct"
            const size_t end = std::min(line.find(',', c), b);
            match = line.compare(c, end - c, controller) == 0;
            c = end + 1;
        }
        if (match) {
            *path = line.substr(b + 1);
            return true;
        }
    }
    return false;
}

std::vector<std::string> cgroup_folders(const std::string& self_cgroup, const std::string& controller,
                                        std::initializer_list<std::string> mounts) {
    std::string path;
    if (!cgroup_path(self_cgroup, controller, &path)) {
        if (controller.empty()) return {};
        path.assign(1, '/');
    }
    std::vector<std::string> folders;
    for (const std::string& root : mounts) {
        for (std::string p = path;;) {
            folders.push_back(root + (p == "/" ? "" : p));
            if (p.empty() || p == "/") break;
            const size_t slash = p.find_last_of('/');
            p = slash == std::string::npos || slash == 0 ? std::string("/") : p.substr(0, slash);
        }
    }
    return folders;
}

std::string read_self_cgroup() {
    std::ifstream f("/proc/self/cgroup");
    std::ostringstream text;
    text << f.rdbuf();
    return text.str();
}

}  // namespace veach
