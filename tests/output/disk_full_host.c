/* A host process of libveach writing on full disks through the C API (check_disk_full.py mounts
 * the small filesystems and checks the files; this program reports what the library returned).
 *
 * The library runs inside someone else's process (Blender, a farm worker): a failed write must
 * come back as VEACH_ERROR_OUTPUT, never end the process. libjpeg's default error handler calls
 * exit(), so a JPEG encoder writing straight to a full disk would end the host inside
 * veachWriteImage; the last line below is printed only if the process is still alive after
 * every write.
 *
 * Usage: disk_full_host SCENE ROOT, where ROOT holds
 *   roomy/            a filesystem with room for every file (the control),
 *   small_EXT/        for each EXT below, a filesystem too small for the image,
 *   small_checkpoint/ one too small for the render's checkpoint.
 * Prints one tab-separated line per write: what, path, error code, last error message. */
#include <stdio.h>
#include <string.h>

#include <veach/veach.h>

static const char* const k_formats[] = {"exr", "hdr", "png", "jpg", "tif", "vpart"};
enum { k_format_count = sizeof(k_formats) / sizeof(k_formats[0]) };

static void report(const char* what, const char* path, VeachError code) {
    /* One line each: the message never holds a tab or a newline (the library's errors are one line). */
    printf("%s\t%s\t%d\t%s\n", what, path, (int)code, code == VEACH_ERROR_NONE ? "" : veachGetLastError());
    fflush(stdout);
}

static VeachRender new_render(VeachScene scene) {
    VeachRender render = veachNewRender(scene);
    veachSetInt(render, "width", 256);
    veachSetInt(render, "spp", 1);
    veachSetInt(render, "threads", 1);
    veachSetString(render, "integrator", "pt");
    return render;
}

int main(int argc, char** argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: %s SCENE ROOT\n", argv[0]);
        return 1;
    }
    const char* root = argv[2];
    char path[4096];
    VeachDevice device = veachNewDevice();
    VeachScene scene = veachNewSceneFromFile(device, argv[1]);
    if (!scene) {
        fprintf(stderr, "cannot load %s: %s\n", argv[1], veachGetLastError());
        return 1;
    }
    VeachRender render = new_render(scene);
    if (veachRender(render) != VEACH_ERROR_NONE) {
        fprintf(stderr, "render failed: %s\n", veachGetLastError());
        return 1;
    }
    for (int i = 0; i < k_format_count; ++i) {
        snprintf(path, sizeof(path), "%s/roomy/ok.%s", root, k_formats[i]);
        report("roomy", path, veachWriteImage(render, path));
    }
    for (int i = 0; i < k_format_count; ++i) {
        snprintf(path, sizeof(path), "%s/small_%s/image.%s", root, k_formats[i], k_formats[i]);
        report("small", path, veachWriteImage(render, path));
    }
    /* A host's sidecar file on a device that is always full. */
    static const char k_text[] = "{\"spp\": 1}\n";
    report("devfull", "/dev/full", veachWriteFile(device, "/dev/full", k_text, sizeof(k_text) - 1));
    veachReleaseRender(render);

    /* A render that keeps its checkpoint on a disk too small for it: the render fails, the host goes on. */
    render = new_render(scene);
    snprintf(path, sizeof(path), "%s/small_checkpoint/ck.checkpoint", root);
    veachSetString(render, "checkpoint", path);
    veachSetFloat(render, "checkpoint_interval", 0.0);
    veachSetInt(render, "spp", 4);
    report("checkpoint", path, veachRender(render));
    veachReleaseRender(render);

    veachReleaseScene(scene);
    veachReleaseDevice(device);
    printf("host alive after every write\n");
    return 0;
}
