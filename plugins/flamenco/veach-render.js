// SPDX-License-Identifier: GPL-3.0-or-later
//
// A Flamenco v3 job type for Veach: renders a glTF scene's frames, each split into sample
// chunks, and merges each frame's parts into its image. Put this file in the `scripts` folder
// beside flamenco-manager; give the Workers that have `veach` the task type "veach"
// (flamenco-worker.yaml: task_types: [veach, ...]).
//
// Per frame F and chunk [A, B) of the frame's --spp N, one task runs Flamenco's `exec` command:
//   veach render SCENE --frame F --spp N --samples A:B -o PARTS/STEM_fF_sA-B.vpart
//                --checkpoint 60 --resume --skip-existing [size, integrator, extra flags]
// and one merge task per frame, depending on that frame's render tasks:
//   veach merge PARTS/STEM_fF_s*.vpart --expect-spp N -o OUTPUT
// Parts are exact film sums, so the merged image is the one a single machine would have rendered
// (see README, "Render farms"). A requeued task resumes from its checkpoint, and one whose part
// is already complete is skipped. Chunks split N as evenly as integers allow:
// A = floor(N c / K), B = floor(N (c + 1) / K) for chunk c of K, as veach-part.sbatch does.

const JOB_TYPE = {
    label: "Veach Render",
    description: "Render a glTF scene with Veach: frames x sample chunks, merged per frame",
    settings: [
        { key: "scene", type: "string", subtype: "file_path", required: true,
          description: "The .gltf or .glb to render (a path every Worker can read)" },
        { key: "output", type: "string", subtype: "file_path", required: true,
          description: "The merged image per frame; {frame} is replaced by the frame number, #### by the number zero-padded to four digits (e.g. /render/shot/frame_####.exr)" },
        { key: "frames", type: "string", required: true, default: "1",
          description: "Frames to render, Flamenco's notation: 1-250, 1,3,10-20 (1..250 works too)" },
        { key: "spp", type: "int32", required: true, default: 1024, description: "Samples per pixel of each frame" },
        { key: "chunks", type: "int32", required: true, default: 16,
          description: "Sample chunks per frame: one render task each (at most spp)" },
        { key: "width", type: "int32", default: 1920, description: "Image width" },
        { key: "height", type: "int32", default: 0, description: "Image height (0: from the camera's aspect ratio)" },
        { key: "integrator", type: "string", choices: ["bdpt", "pt", "lt"], default: "bdpt",
          description: "Veach's integrator" },
        { key: "threads", type: "int32", default: 0,
          description: "Threads per render task (0: the CPUs the Worker's process may use)" },
        { key: "parts_dir", type: "string", subtype: "dir_path", default: "",
          description: "Folder for the part files (empty: parts/ beside the output)" },
        { key: "extra_args", type: "string", default: "",
          description: "Further `veach render` flags, separated by spaces (e.g. --seed 3 --max-depth 16)" },
        { key: "veach", type: "string", default: "veach",
          description: "The veach command on the Workers (a Manager variable such as {veach} works)" },
    ],
};

function compileJob(job) {
    const s = job.settings;
    const spp = toWholeNumber(s.spp, "spp", 1);
    const chunks = toWholeNumber(s.chunks, "chunks", 1);
    if (chunks > spp) throw `chunks (${chunks}) cannot exceed spp (${spp}): a chunk holds at least one sample`;
    if (!s.scene) throw "no scene given";
    if (!s.output) throw "no output given";
    const frames = explodeFrames(s.frames);
    if (frames.length > 1 && !/\{frame\}|#/.test(String(s.output)))
        throw `several frames (${s.frames}) need {frame} or #### in the output, or every merge writes the same file`;

    const exe = s.veach || "veach";
    const partsDir = s.parts_dir ? s.parts_dir : path.join(path.dirname(s.output), "parts");
    const stem = path.stem(s.scene);
    const common = ["--spp", String(spp)];
    if (s.width) common.push("--width", String(toWholeNumber(s.width, "width", 1)));
    if (s.height) common.push("--height", String(toWholeNumber(s.height, "height", 1)));
    if (s.integrator) common.push("--integrator", String(s.integrator));
    if (s.threads) common.push("--threads", String(toWholeNumber(s.threads, "threads", 1)));
    const extra = splitArgs(s.extra_args);

    for (const frame of frames) {
        const parts = [];
        const renders = [];
        for (let c = 0; c < chunks; c++) {
            const a = Math.floor((spp * c) / chunks);
            const b = Math.floor((spp * (c + 1)) / chunks);
            const part = path.join(partsDir, `${stem}_f${frame}_s${a}-${b}.vpart`);
            parts.push(part);
            const task = author.Task(`render-f${frame}-s${a}-${b}`, "veach");
            task.addCommand(author.Command("exec", {
                exe: exe,
                args: ["render", s.scene, "--frame", String(frame)].concat(common, ["--samples", `${a}:${b}`], extra,
                    ["--checkpoint", "60", "--resume", "--skip-existing", "-o", part]),
            }));
            job.addTask(task);
            renders.push(task);
        }
        const merge = author.Task(`merge-f${frame}`, "veach");
        merge.addCommand(author.Command("exec", {
            exe: exe,
            args: ["merge"].concat(parts, ["--expect-spp", String(spp), "-o", withFrame(String(s.output), frame)]),
        }));
        for (const r of renders) merge.addDependency(r);
        job.addTask(merge);
    }
}

// The output of one frame, as `veach render --frames` names it: {frame} becomes the number, each
// run of # the number zero-padded to the run's length (Blender's ####).
function withFrame(output, frame) {
    return output.split("{frame}").join(String(frame))
        .replace(/#+/g, (run) => String(frame).padStart(run.length, "0"));
}

// Flamenco passes int32 settings as numbers; a hand-written job may pass strings.
function toWholeNumber(value, name, least) {
    const n = Number(value);
    if (!Number.isInteger(n) || n < least) throw `${name} must be a whole number of at least ${least}, not '${value}'`;
    return n;
}

// Every frame of a range, in order: frameChunker with chunks of one frame ("1-3,7" -> 1, 2, 3, 7).
function explodeFrames(range) {
    const out = [];
    for (const chunk of frameChunker(String(range), 1)) {
        const n = Number(chunk);
        if (!Number.isInteger(n)) throw `frames '${range}': '${chunk}' is not a frame number`;
        out.push(n);
    }
    if (out.length === 0) throw `frames '${range}': no frame`;
    return out;
}

function splitArgs(text) {
    return String(text || "").split(" ").filter((arg) => arg.length > 0);
}
