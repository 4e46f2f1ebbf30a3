/* Veach: the C API for host applications.
 *
 * Modelled on Embree's and Open Image Denoise's APIs: opaque reference-counted handles, an error
 * callback plus a per-thread last-error string, and string-keyed typed options, so that the ABI
 * stays stable for any language that can call C (ctypes, cffi, C#, Rust). No C++ exception
 * crosses this boundary: every failure becomes a VeachError code and a one-line message.
 *
 *   VeachDevice d = veachNewDevice();
 *   VeachScene  s = veachNewSceneFromFile(d, "cornell.gltf");
 *   VeachRender r = veachNewRender(s);
 *   veachSetInt(r, "width", 512); veachSetInt(r, "spp", 64); veachSetString(r, "integrator", "pt");
 *   veachRender(r);                 (or veachRenderAsync + veachWaitRender/veachCancelRender)
 *   veachWriteImage(r, "out.png");  (or veachGetPass into your own buffer)
 *   veachReleaseRender(r); veachReleaseScene(s); veachReleaseDevice(d);
 *
 * Options a scene needs before it is loaded (glTF scene index, KHR_materials_variants variant, spot
 * profile, environment) go through veachNewScene + veachSetScene* + veachLoadSceneFile.
 *
 * Strings come back through caller-owned buffers (veachGet*String): `size` bytes at most,
 * always NUL-terminated when size > 0, and *length (if not NULL) set to the full length, so a
 * call with size 0 asks for the length. Lists are one item per line ("a\nb").
 *
 * There is no global mutable state: any number of devices, scenes and renders may live and render
 * at once in one process. Handles may be used from any thread, but a render's options must not
 * change while it runs.
 */
#ifndef VEACH_VEACH_H
#define VEACH_VEACH_H

#include <stdbool.h>
#include <stddef.h>

#define VEACH_VERSION_MAJOR 0
#define VEACH_VERSION_MINOR 8
#define VEACH_VERSION_PATCH 0
/* major * 10000 + minor * 100 + patch, as veachGetVersion() returns it. */
#define VEACH_VERSION (VEACH_VERSION_MAJOR * 10000 + VEACH_VERSION_MINOR * 100 + VEACH_VERSION_PATCH)

#if defined(_WIN32)
#if defined(VEACH_BUILDING_LIBRARY)
#define VEACH_API __declspec(dllexport)
#else
#define VEACH_API __declspec(dllimport)
#endif
#else
#define VEACH_API __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef enum VeachError {
    VEACH_ERROR_NONE = 0,
    VEACH_ERROR_INVALID_ARGUMENT = 1,  /* a null handle, an unknown option, a value out of range */
    VEACH_ERROR_INVALID_OPERATION = 2, /* e.g. changing options or rendering while a render runs */
    VEACH_ERROR_BAD_INPUT = 3,         /* the scene file or buffer is malformed or unreadable */
    VEACH_ERROR_OUTPUT = 4,            /* an image could not be written */
    VEACH_ERROR_CANCELLED = 5,         /* the render was cancelled; its partial image is available */
    VEACH_ERROR_OUT_OF_MEMORY = 6,
    VEACH_ERROR_UNKNOWN = 7
} VeachError;

typedef enum VeachStatus {
    VEACH_STATUS_IDLE = 0,      /* never rendered */
    VEACH_STATUS_RUNNING = 1,   /* an asynchronous render is in progress */
    VEACH_STATUS_DONE = 2,      /* finished: every requested sample (or the time limit) */
    VEACH_STATUS_CANCELLED = 3, /* stopped early by veachCancelRender or the progress callback */
    VEACH_STATUS_FAILED = 4     /* the error went to the callback and to veachWaitRender's caller */
} VeachStatus;

typedef struct VeachDeviceImpl* VeachDevice;
typedef struct VeachSceneImpl* VeachScene;
typedef struct VeachRenderImpl* VeachRender;

/* Called on the thread where the error happened (a render's own thread for asynchronous renders).
 * A failing call made from inside the callback is not reported to it again (its last error is
 * still set): no recursion. */
typedef void (*VeachErrorFunction)(void* user, VeachError code, const char* message);

/* Called after each pass of samples with the fraction done in [0, 1] and the estimated seconds
 * left. Return false to cancel. Called on the rendering thread; do not release the render from it. */
typedef bool (*VeachProgressFunction)(void* user, double fraction, double eta_seconds);

/* ---- Version and errors ------------------------------------------------------------------- */

/* VEACH_VERSION of the library actually loaded (compare with the header's to detect a mismatch). */
VEACH_API int veachGetVersion(void);
VEACH_API const char* veachGetVersionString(void);

/* The message of the last failed call on this thread, "" when it succeeded. Every call that can
 * fail resets it on entry (retain, release, cancel and these getters do not). The pointer stays
 * valid until this thread's next API call. */
VEACH_API const char* veachGetLastError(void);
VEACH_API VeachError veachGetLastErrorCode(void);

/* ---- Device: the error callback and defaults shared by its scenes and renders ------------- */

VEACH_API VeachDevice veachNewDevice(void);
VEACH_API void veachRetainDevice(VeachDevice device);
VEACH_API void veachReleaseDevice(VeachDevice device);
VEACH_API void veachSetDeviceErrorFunction(VeachDevice device, VeachErrorFunction fn, void* user);
/* Device queries (since 0.2):
 *   int:    peak_memory_bytes (the process's peak resident set so far, 0 where unknown)
 *   string: integrators, filters, passes, exr_codecs (the names the options accept, one a line);
 *           options (since 0.8: every scene and render option as a JSON array, one object each:
 *           name, object ("scene" or "render"), type, default, min and max (numbers), choices
 *           (names), help, identity (part of the render's identity), flag (the veach command's));
 *           color_config ("$OCIO=/path" or "built-in": the OpenColorIO config in use),
 *           color_displays, color_looks, color_views:DISPLAY (one a line). A config that cannot be
 *           read is VEACH_ERROR_BAD_INPUT. */
VEACH_API VeachError veachGetDeviceInt(VeachDevice device, const char* name, long long* value);
VEACH_API VeachError veachGetDeviceString(VeachDevice device, const char* name, char* buffer, size_t size,
                                          size_t* length);
/* Writes `size` bytes to `path` the way the library writes its images and checkpoints (since
 * 0.3): into a temporary file created beside it (O_EXCL | O_NOFOLLOW, a random name), every write
 * and the close checked, fsync'ed, then renamed over `path`; on any failure the temporary file is
 * removed and VEACH_ERROR_OUTPUT returned, leaving `path` as it was. An existing character
 * device or FIFO (/dev/stdout) is written in place. For a host's own sidecar files (the veach
 * command's --stats-json). */
VEACH_API VeachError veachWriteFile(VeachDevice device, const char* path, const void* data, size_t size);
/* Whether veachWriteFile(device, path, ...) could write `path`, without writing it (since 0.5):
 * its folder exists and a file can really be created in it (one is created and removed at once:
 * permission bits say nothing for root or about a read-only mount), and `path` is not a folder.
 * An existing device or FIFO passes. VEACH_ERROR_OUTPUT with one line naming the file otherwise.
 * For checking a host's sidecar files (stats, checkpoints) before a render spends its time. */
VEACH_API VeachError veachCheckFile(VeachDevice device, const char* path);

/* ---- Scenes: imported once, immutable, shared by any number of renders -------------------- */

/* Any registered format by extension (.gltf, .glb). NULL on failure (VEACH_ERROR_BAD_INPUT). */
VEACH_API VeachScene veachNewSceneFromFile(VeachDevice device, const char* path);
/* A scene held in memory, e.g. a .glb a host produced: `format` is an extension ("glb"); relative
 * URIs resolve against `base_dir` (may be NULL). The bytes are copied. */
VEACH_API VeachScene veachNewSceneFromMemory(VeachDevice device, const void* data, size_t size, const char* format,
                                             const char* base_dir);
/* The same in steps, for options that shape the scene (since 0.2): an empty scene, its options, then one
 * load. Options (an unknown name, a wrong type or a bad value is VEACH_ERROR_INVALID_ARGUMENT; any
 * option after the load but time is VEACH_ERROR_INVALID_OPERATION):
 *   int:    scene_index (glTF scene, -1 = the file's default), allow_external_files (0 or 1: URIs
 *           may point outside the file's folder)
 *   float:  env_strength (>= 0, default 1), env_rotate (degrees about +Y, as a Mapping node's Z
 *           rotation in Blender's world shader), time (seconds, since 0.4: the scene's animations,
 *           skins and morph targets evaluated at that time; unset, reading NaN, the file's nodes
 *           are placed as they stand and skins and morph targets are not applied; set again after
 *           the load of a scene loaded with a time, it poses that scene at the new time without
 *           reading the file again: a sequence; VEACH_ERROR_INVALID_OPERATION while a render of the
 *           scene runs, or for a scene loaded without a time)
 *   string: variant (KHR_materials_variants; an unknown name fails the load, listing the file's),
 *           spot_falloff ("auto", "blender", "gltf"), default_material ("auto", "blender", "gltf":
 *           what a primitive without a material is; auto: Cycles' default surface, Lambertian 0.8,
 *           when asset.generator names Blender, else the glTF spec's default), env_map (an equirectangular image file;
 *           unreadable fails the load with VEACH_ERROR_BAD_INPUT), env_color ("R,G,B": a uniform
 *           linear radiance; excludes env_map), animation (with time: "all", the default, plays
 *           every animation at once; else one animation's name or index; one the file lacks fails
 *           the load with VEACH_ERROR_BAD_INPUT, listing the file's), shutter (since 0.7, with
 *           time: motion blur, "OPEN,CLOSE" in seconds relative to time, e.g. "-0.0104,0.0104" for
 *           Blender's shutter 0.5 at 24 fps; each camera sample sees the scene at one time in
 *           [time + OPEN, time + CLOSE]; the camera moves, posed at three times across the shutter
 *           and interpolated; "" (the default) or OPEN = CLOSE: none; OPEN > CLOSE or a non-finite
 *           value is VEACH_ERROR_INVALID_ARGUMENT; set without time, the load fails with
 *           VEACH_ERROR_INVALID_OPERATION; a sequence keeps it for every time)
 * After loading, read-only: int triangles, cameras and what scene repair changed
 * (repaired_invalid_indices, repaired_nonfinite_triangles, repaired_degenerate_triangles,
 * repaired_duplicate_triangles, repaired_normals_replaced, repaired_normals_normalized,
 * repaired_uvs_replaced, repaired_colors_replaced, repaired_lights_dropped); string source (the
 * path loaded), features (the scene features found), warnings (import warnings), info (since 0.8:
 * JSON of what the scene holds: the file's scenes, variants and animations, cameras, lights by
 * kind, meshes, instances, triangles, materials, textures with sizes, features, repairs); and
 * every option.
 * A scene must be loaded before veachNewRender. */
VEACH_API VeachScene veachNewScene(VeachDevice device);
VEACH_API VeachError veachSetSceneInt(VeachScene scene, const char* name, long long value);
VEACH_API VeachError veachSetSceneFloat(VeachScene scene, const char* name, double value);
VEACH_API VeachError veachSetSceneString(VeachScene scene, const char* name, const char* value);
VEACH_API VeachError veachLoadSceneFile(VeachScene scene, const char* path);
VEACH_API VeachError veachLoadSceneMemory(VeachScene scene, const void* data, size_t size, const char* format,
                                          const char* base_dir);
VEACH_API VeachError veachGetSceneInt(VeachScene scene, const char* name, long long* value);
VEACH_API VeachError veachGetSceneFloat(VeachScene scene, const char* name, double* value);
VEACH_API VeachError veachGetSceneString(VeachScene scene, const char* name, char* buffer, size_t size, size_t* length);
VEACH_API void veachRetainScene(VeachScene scene);
VEACH_API void veachReleaseScene(VeachScene scene);
VEACH_API int veachGetSceneCameraCount(VeachScene scene);
/* The camera's name (valid while the scene lives), NULL for an index out of range. */
VEACH_API const char* veachGetSceneCameraName(VeachScene scene, int index);

/* ---- Renders: options, rendering, results ------------------------------------------------- */

VEACH_API VeachRender veachNewRender(VeachScene scene);
VEACH_API void veachRetainRender(VeachRender render);
/* Releasing the last reference cancels a running render and waits for it. */
VEACH_API void veachReleaseRender(VeachRender render);

/* Options (the name decides the type; a wrong type or unknown name is VEACH_ERROR_INVALID_ARGUMENT,
 * and so is a value outside the option's range, with a message naming the option: "spp must be
 * at least 1"). Names, types, defaults and ranges are one table, which the device query
 * "options" returns; since 0.8 width is 1 to 65536 and threads 0 to 4096, as the command's flags.
 *   int:    width (default 1920), height (0 = from the camera's aspect), spp (64), seed (0),
 *           max_depth (64), threads (0 = the CPUs the process may use: its affinity mask, lowered
 *           to a cgroup CPU quota, since 0.6), bits (PNG/TIFF: 8 or 16), quality (JPEG),
 *           half (EXR half floats: 0 or 1), aovs (1: record the depth, normal and albedo passes),
 *           bdpt_s, bdpt_t (bdpt: render only the strategy with s light and t camera vertices,
 *           unweighted, for verification; -1 = all), resume (0 or 1: start from the checkpoint
 *           file when it exists), sample_begin, sample_end (since 0.4: render only sample
 *           indices [sample_begin, sample_end) of the spp; 0 <= begin < end <= spp, end 0 = spp;
 *           not with noise or time_limit), transparent (since 0.5: 1 is Cycles' Film >
 *           Transparent: camera rays that escape see no environment, which still lights the
 *           scene, and the combined pass's alpha is the fraction of the pixel's camera samples
 *           that hit geometry; not with sample_begin/sample_end or pixelbounds), denoise (since 0.7: 1 denoises the
 *           combined pass after the render, a feature-guided regression on two half images of
 *           the render (README "Denoising"), biased; the rendered image stays as the pass "noisy";
 *           not with sample_begin/sample_end or pixelbounds), snapshots
 *           (since 0.8: 1 keeps the film so far at every pass boundary for veachGetPass and
 *           veachWriteImage during an asynchronous render)
 *   float:  time_limit (seconds, 0 = none), filter_width (pixels, default 1; Blender's default is
 *           1.5 for its smooth filters), exposure (stops), gamma,
 *           noise (adaptive sampling: a pixel stops once its estimated relative error is below
 *           this; 0 = off, every pixel gets spp), checkpoint_interval (seconds: keep the
 *           checkpoint file up to date at the first pass boundary after this long, 0 = every
 *           pass, negative = never write: the default)
 *   string: integrator ("auto", the default: bidirectional path tracing with the strategies
 *           the scene needs; "bdpt", "pt", "lt"), camera (a name or an index, "" = the first),
 *           filter ("box", "gaussian", "blackman-harris"; Cycles' pixel filters),
 *           sampler ("sobol", "random"), display, view, look (OpenColorIO, for PNG/JPEG/TIFF),
 *           exr_codec (none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab; "zip:N" and
 *           "dwaa:N" set a level), passes (EXR: "" for plain RGBA, else a comma-separated list
 *           from combined, depth, normal, albedo, variance written as a multi-layer EXR with
 *           Blender's names; depth, normal and albedo turn aovs on; with denoise = 1 also noisy,
 *           denoising_normal, denoising_albedo, denoising_depth, which without it fail the render
 *           with VEACH_ERROR_INVALID_ARGUMENT), checkpoint (a file holding
 *           the film's state between passes, so that a killed render resumes to the same image;
 *           a checkpoint of another render or scene is refused with VEACH_ERROR_BAD_INPUT; not
 *           deleted by the library: remove it once the image is safe), pixelbounds (since 0.4:
 *           "X0,X1,Y0,Y1" renders only pixels [X0,X1) x [Y0,Y1) of the frame, pbrt's order;
 *           "" = the whole frame; not with noise; light-tracing splats still land anywhere)
 * Results, read-only, through the getters: int result_width, result_height, result_spp (samples
 *   every pixel completed), result_resumed_spp (from the checkpoint), result_complete (1 unless
 *   cancelled before the requested samples), result_camera_samples, result_rays,
 *   result_nonfinite_samples (dropped), result_threads (since 0.6: the worker threads the
 *   render ran on), estimated_memory_bytes (since 0.8: what rendering with the current options
 *   would allocate beyond the scene, the estimate the render checks before it starts); float
 *   progress, eta_seconds, render_seconds, build_seconds, denoise_seconds (since 0.7: 0 without
 *   denoise); string result_camera, result_integrator (the one that rendered), result_strategies
 *   (since 0.7: what the default integrator "auto" chose, "pt" or "bdpt:" and its strategy
 *   families' letters; empty for the others), result_warnings. Every option can be read back too. */
VEACH_API VeachError veachSetInt(VeachRender render, const char* name, long long value);
VEACH_API VeachError veachSetFloat(VeachRender render, const char* name, double value);
VEACH_API VeachError veachSetString(VeachRender render, const char* name, const char* value);
VEACH_API VeachError veachGetInt(VeachRender render, const char* name, long long* value);
VEACH_API VeachError veachGetFloat(VeachRender render, const char* name, double* value);
VEACH_API VeachError veachGetString(VeachRender render, const char* name, char* buffer, size_t size, size_t* length);

VEACH_API void veachSetProgressFunction(VeachRender render, VeachProgressFunction fn, void* user);

/* Renders on the calling thread (TBB workers in an arena of `threads`). Returns
 * VEACH_ERROR_CANCELLED when stopped early; the partial image is still available. */
VEACH_API VeachError veachRender(VeachRender render);
/* Starts the same render on a thread of its own and returns at once. */
VEACH_API VeachError veachRenderAsync(VeachRender render);
/* Waits up to timeout_ms (negative: forever) and returns the status. A failed render's error is
 * reported to this caller too (last error). Called from the render's own thread (its progress or
 * error callback) it would wait for itself: it returns VEACH_STATUS_FAILED at once, with
 * VEACH_ERROR_INVALID_OPERATION as the last error. */
VEACH_API VeachStatus veachWaitRender(VeachRender render, int timeout_ms);
VEACH_API VeachStatus veachGetRenderStatus(VeachRender render);
/* Asks a running render to stop; returns at once. The render stops within one 16x16 tile.
 * It only sets an atomic flag, but it is not async-signal-safe by contract: a program that stops
 * on SIGINT/SIGTERM should set its own std::atomic<bool> (or sig_atomic_t) in the handler and
 * call veachCancelRender from ordinary code, e.g. a thread polling veachWaitRender(r, 50), or
 * by returning false from the progress callback (slower: it runs once per pass). The veach
 * command does the former. */
VEACH_API void veachCancelRender(VeachRender render);

/* Copies a finished (or cancelled) render's pass into `dst`; during an asynchronous render (since
 * 0.8) the film so far: resolved at a pass boundary, so every pass of it holds the same samples,
 * and result_width, result_height and result_spp describe it. With the option snapshots = 1 one
 * is kept at every pass boundary; without it a call during the render asks for the next
 * boundary's, and until one exists the call is VEACH_ERROR_INVALID_OPERATION. The snapshot of
 * the last pass equals the final image. `dst` which holds `dst_bytes` bytes: 4
 * floats per pixel, row 0 at the top, rows `row_stride_bytes` apart (0 = result_width * 4 *
 * sizeof(float)). A destination smaller than (result_height - 1) * stride + one row is refused
 * with VEACH_ERROR_INVALID_ARGUMENT before anything is written (since 0.6; 0.5's form without
 * `dst_bytes` remains in the library for programs linked against it). Passes: "combined" (alias
 * "color"): RGBA scene-linear Rec.709 (alpha 1, or coverage with transparent = 1: premultiplied,
 * as Cycles'); with aovs = 1 also "depth"
 * (z, z, z, 1: camera-space Z of the first hit, 1e10 where nothing was hit, as Blender's Z pass),
 * "normal" and "albedo" (x, y, z, 1); always "variance" (of each channel's pixel mean: r, g, b, 1)
 * and "samples" (since 0.3: the camera samples averaged into the pixel, n, n, n, 1: fewer than spp
 * where adaptive sampling stopped the pixel early or a non-finite sample was dropped); with
 * denoise = 1 (since 0.7) "noisy" (the combined colour before denoising, alpha 1) and the
 * denoiser's features "denoising_normal", "denoising_albedo" (x, y, z, 1: of the first surface
 * seen, through mirrors and smooth glass) and "denoising_depth" (z, z, z, 1: the first hit's). */
VEACH_API VeachError veachGetPass(VeachRender render, const char* pass, float* dst, size_t dst_bytes,
                                  size_t row_stride_bytes);
/* Writes the combined pass (and for EXR the `passes` option's layers) through the output driver
 * (during an asynchronous render, since 0.8: the film so far, as veachGetPass gives it, tagged
 * veach:complete "no"; not a .vpart):
 * format from the extension (.exr .hdr .png .jpg .tif); EXR/HDR scene-linear, PNG/JPEG/TIFF
 * through the OpenColorIO view (display, view, look, exposure, gamma), with the bits, quality,
 * half and exr_codec options; numeric metadata as int and float attributes (since 0.8), the
 * option attributes' NAME=VALUE lines added. Metadata: Software, veach:scene, veach:camera, veach:spp,
 * veach:spp_requested, veach:complete, veach:seed, veach:integrator, veach:filter,
 * veach:render_seconds (and veach:resumed_spp; for a part, veach:samples "A:B" unless it starts at
 * sample 0 of the whole frame, and veach:pixelbounds for a tile; with noise > 0, since 0.8,
 * veach:spp is the fewest samples any pixel took, with veach:spp_mean and veach:spp_max; the
 * "samples" pass is the EXR layer "Sample Count"). Atomic: never a half-written file.
 * A path ending in .vpart (since 0.4) writes a part file instead: the film's exact double sums for
 * the render's sample range and pixel bounds, its light-tracing splats over the whole frame, and
 * the render's identity (a hash of every image-shaping setting and of the content, never the
 * path, of every file the scene read), zlib-compressed with a CRC. It reads only the render's
 * own finished result (and the scene's source name), so a host rendering a sequence may write
 * frame N on a thread of its own while the scene is posed at frame N+1 and renders it, the
 * file's fsync hidden behind that render: the veach command does. */
VEACH_API VeachError veachWriteImage(VeachRender render, const char* path);
/* Whether veachWriteImage(render, path) could write `path` with the render's current options,
 * without rendering or writing anything (since 0.5), so that a farm task refuses a typo at once
 * instead of after an hour of rendering: VEACH_ERROR_INVALID_ARGUMENT for an unknown format
 * (extension) and, for PNG/JPEG/TIFF, a display, view or look the OpenColorIO config lacks (or a
 * config that cannot be read); VEACH_ERROR_OUTPUT when the folder does not exist or no file can
 * be created in it (as veachCheckFile), `path` is a folder or, for an image format (not .vpart),
 * libveach's image module (libveach_image_io.so, beside the library) cannot be opened. Works on a render that has not run,
 * even one of an empty scene. One line naming the file either way. */
VEACH_API VeachError veachCheckOutput(VeachRender render, const char* path);
/* The metadata of a file veachWriteImage wrote (since 0.5), "key=value" one a line, through the
 * caller's buffer: every format's keys as veachWriteImage names them (veach:spp, veach:complete,
 * veach:spp_requested, veach:samples, ...; JPEG/TIFF descriptions and HDR header lines split
 * into keys). For a .vpart, the keys an image of that part would carry (veach:spp,
 * veach:spp_requested, veach:samples and veach:pixelbounds by the same rules, veach:seed, veach:camera, veach:integrator), read from its header. VEACH_ERROR_BAD_INPUT
 * when the file cannot be read. The veach command's --skip-existing reads it. */
VEACH_API VeachError veachReadImageMetadata(VeachDevice device, const char* path, char* buffer, size_t size,
                                            size_t* length);

/* ---- Part files: renders split across machines (since 0.4) -------------------------------- */

/* Sums part files (.vpart) into a render that holds the merged result, to be written with
 * veachWriteImage in any format (or as one .vpart when the parts form one sample range over one
 * rectangle) and read with veachGetPass / veachGetInt("result_spp"). It cannot be rendered.
 * Merging is exact: the double sums add in sample order, so path-traced parts give the single
 * render's image bit for bit, and light-tracing splats agree to summation order. expect_spp > 0
 * requires the parts to cover sample indices [0, expect_spp) of every pixel exactly (0: any
 * cover). NULL on failure, with VEACH_ERROR_BAD_INPUT and one line naming the files for parts
 * of different renders, parts overlapping in samples and pixels, gaps (with expect_spp) and
 * unreadable or corrupt parts. */
VEACH_API VeachRender veachNewRenderFromParts(VeachDevice device, const char* const* paths, size_t count,
                                             long long expect_spp);

#ifdef __cplusplus
}
#endif

#endif /* VEACH_VEACH_H */
