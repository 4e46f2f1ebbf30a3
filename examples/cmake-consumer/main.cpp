// Renders a scene through the header-only C++ wrapper (veach.hpp) of an installed Veach.
//   veach_consumer SCENE OUT.png|OUT.exr [WIDTH] [SPP]
#include <cstdio>
#include <cstdlib>
#include <veach/veach.hpp>

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s SCENE OUT [WIDTH] [SPP]\n", argv[0]);
        return 1;
    }
    try {
        veach::Device device;
        veach::Scene scene(device, argv[1]);
        veach::Render render(scene);
        render.set("width", argc > 3 ? std::atoi(argv[3]) : 256)
            .set("spp", argc > 4 ? std::atoi(argv[4]) : 16)
            .set("integrator", "pt");
        render.on_progress([](double fraction, double) {
            std::fprintf(stderr, "\rProgress: %3d%%", static_cast<int>(fraction * 100));
            return true;
        });
        render.render();
        render.write_image(argv[2]);
        std::fprintf(stderr, "\nveach %s: wrote %s (%dx%d)\n", veach::version_string(), argv[2], render.width(),
                     render.height());
    } catch (const veach::Error& e) {
        std::fprintf(stderr, "error %d: %s\n", static_cast<int>(e.code()), e.what());
        return e.code() == VEACH_ERROR_BAD_INPUT ? 2 : 3;
    }
    return 0;
}
