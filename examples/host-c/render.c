/* A host application in C: load a glTF scene, render it with a progress callback, write a PNG.
 *   cc render.c $(pkg-config --cflags --libs veach) -o render
 *   ./render scene.gltf out.png [width] [spp] */
#include <stdio.h>
#include <stdlib.h>

#include <veach/veach.h>

static void on_error(void* user, VeachError code, const char* message) {
    (void)user;
    fprintf(stderr, "veach error %d: %s\n", (int)code, message);
}

static bool on_progress(void* user, double fraction, double eta_seconds) {
    int* last_percent = (int*)user;
    int percent = (int)(fraction * 100.0);
    if (percent != *last_percent) fprintf(stderr, "\r%3d%%  ETA %5.1f s", percent, eta_seconds);
    *last_percent = percent;
    return true; /* false would cancel the render */
}

int main(int argc, char** argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: %s SCENE.gltf OUT.png [WIDTH] [SPP]\n", argv[0]);
        return 1;
    }
    if (veachGetVersion() / 10000 != VEACH_VERSION_MAJOR) {
        fprintf(stderr, "libveach %s does not match this program's header\n", veachGetVersionString());
        return 1;
    }
    int status = 3;
    VeachDevice device = veachNewDevice();
    veachSetDeviceErrorFunction(device, on_error, NULL);
    VeachScene scene = veachNewSceneFromFile(device, argv[1]);
    if (!scene) {
        veachReleaseDevice(device);
        return 2; /* the callback printed why; veachGetLastError() has it too */
    }
    VeachRender render = veachNewRender(scene);
    int last_percent = -1;
    veachSetInt(render, "width", argc > 3 ? atoi(argv[3]) : 256);
    veachSetInt(render, "spp", argc > 4 ? atoi(argv[4]) : 16);
    veachSetString(render, "integrator", "pt");
    veachSetProgressFunction(render, on_progress, &last_percent);
    if (veachRender(render) == VEACH_ERROR_NONE && veachWriteImage(render, argv[2]) == VEACH_ERROR_NONE) {
        long long w = 0, h = 0;
        veachGetInt(render, "result_width", &w);
        veachGetInt(render, "result_height", &h);
        fprintf(stderr, "\nwrote %s (%lldx%lld)\n", argv[2], w, h);
        status = 0;
    }
    veachReleaseRender(render);
    veachReleaseScene(scene);
    veachReleaseDevice(device);
    return status;
}
