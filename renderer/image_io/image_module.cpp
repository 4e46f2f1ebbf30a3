#include "image_io/image_module.h"

#include <dlfcn.h>
#include <link.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "core/one_line.h"

namespace veach {

namespace {

// The folder of the object this code is linked into: libveach.so's when it is the library, the
// program's own when the renderer is linked statically (tests, tools). dladdr names the main
// program by its argv[0], so the program is found through /proc/self/exe instead.
std::string own_folder() {
    Dl_info info{};
    struct link_map* map = nullptr;
    std::string file;
    if (dladdr1(reinterpret_cast<void*>(&image_codec), &info, reinterpret_cast<void**>(&map), RTLD_DL_LINKMAP) &&
        map && map->l_name && *map->l_name) {
        file = map->l_name;
    } else {
        std::vector<char> buffer(4096);
        const ssize_t n = readlink("/proc/self/exe", buffer.data(), buffer.size());
        if (n > 0 && static_cast<size_t>(n) < buffer.size()) file.assign(buffer.data(), static_cast<size_t>(n));
    }
    const size_t slash = file.find_last_of('/');
    return slash == std::string::npos ? std::string() : file.substr(0, slash + 1);
}

struct Loaded {
    const image_io::Codec* codec = nullptr;
    std::string error;
};

Loaded load() {
    Loaded loaded;
    // Beside this library first: an installed or build tree's own module, whatever the library
    // path says. Then the library path, for a program linked with the renderer whose RUNPATH
    // names the module's folder.
    std::vector<std::string> candidates;
    const std::string folder = own_folder();
    if (!folder.empty()) candidates.push_back(folder + k_image_module_name);
    candidates.push_back(k_image_module_name);
    std::string first_error;
    for (const std::string& candidate : candidates) {
        // RTLD_LOCAL: OpenImageIO's libraries serve the module only; never closed, since
        // OpenImageIO keeps threads and static state for the life of the process.
        void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* e = dlerror();
            // A module that exists but cannot load (a missing dependency) is the reason to report.
            const std::string why = e ? e : "cannot open";
            if (first_error.empty() || (why.find("No such file") == std::string::npos &&
                                        first_error.find("No such file") != std::string::npos))
                first_error = why;
            continue;
        }
        auto entry = reinterpret_cast<image_io::ModuleEntry>(dlsym(handle, image_io::k_module_entry));
        const image_io::Codec* codec = entry ? entry(image_io::k_interface_version, VEACH_VERSION_STRING) : nullptr;
        if (!codec) {
            loaded.error = std::string(k_image_module_name) + " (" + candidate +
                           ") is not the image module of veach " VEACH_VERSION_STRING
                           " (another version or build); reinstall veach";
            return loaded;
        }
        loaded.codec = codec;
        return loaded;
    }
    // dlerror names the file it tried (beside this library first).
    loaded.error = "cannot load veach's image module (OpenImageIO, for image files): " + one_line(first_error);
    return loaded;
}

}  // namespace

const image_io::Codec& image_codec() {
    static const Loaded loaded = load();
    if (!loaded.codec) throw ImageModuleError(loaded.error);
    return *loaded.codec;
}

}  // namespace veach
