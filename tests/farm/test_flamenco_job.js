// The Flamenco job type (plugins/flamenco/veach-render.js) compiled under node, with stand-ins for
// the globals Flamenco Manager gives a job compiler script (author.Task / author.Command, path,
// frameChunker, print, alert) and a job object with settings and addTask.
//
// What must hold: every frame gets one render task per sample chunk whose --samples ranges tile
// [0, spp) exactly with no overlap (the merge refuses anything else), each an `exec` of
// `veach render ... --frame F --samples A:B -o PART.vpart` with resume and skip-existing; one merge
// task per frame lists exactly that frame's parts, --expect-spp spp and the frame's output, and
// depends on exactly that frame's render tasks; bad settings are refused at compile time.
// Runs on Debian's nodejs (18) with node:test; `node test_flamenco_job.js`.
"use strict";
const test = require("node:test");
const assert = require("node:assert");
const fs = require("node:fs");
const nodePath = require("node:path");
const vm = require("node:vm");

const script = fs.readFileSync(nodePath.join(__dirname, "..", "..", "plugins", "flamenco", "veach-render.js"), "utf8");

// Flamenco's frameChunker: "1-10,20..25,40" -> chunks of at most `size` frames, in order,
// duplicates removed, each written as "A-B" or single frames joined by commas.
function frameChunker(range, size) {
    const frames = new Set();
    for (const part of String(range).replace(/\.\./g, "-").split(",")) {
        const ends = part.split("-").map((x) => x.trim());
        if (ends.length > 2 || ends.some((x) => !/^\d+$/.test(x))) throw new Error(`invalid range "${range}"`);
        const a = Number(ends[0]), b = Number(ends[ends.length - 1]);
        for (let f = a; f <= b; f++) frames.add(f);
    }
    const sorted = [...frames].sort((x, y) => x - y);
    const chunks = [];
    for (let i = 0; i < sorted.length; i += size) {
        const c = sorted.slice(i, i + size);
        chunks.push(c.length === 1 ? String(c[0]) : `${c[0]}-${c[c.length - 1]}`);
    }
    return chunks;
}

function compile(settings) {
    const tasks = [];
    const author = {
        Task: (name, type) => ({
            name, type, commands: [], dependencies: [],
            addCommand(c) { this.commands.push(c); },
            addDependency(t) { this.dependencies.push(t); },
        }),
        Command: (name, parameters) => ({ name, parameters }),
    };
    const path = {
        join: (...p) => nodePath.posix.join(...p),
        dirname: (p) => nodePath.posix.dirname(p),
        basename: (p) => nodePath.posix.basename(p),
        stem: (p) => nodePath.posix.basename(p, nodePath.posix.extname(p)),
    };
    const context = vm.createContext({ author, path, frameChunker, print: () => {}, alert: () => {} });
    vm.runInContext(script, context, { filename: "veach-render.js" });
    const job = { settings, metadata: {}, addTask: (t) => tasks.push(t) };
    context.job = job;
    vm.runInContext("compileJob(job)", context);
    const jobType = vm.runInContext("JOB_TYPE", context);
    return { tasks, jobType };
}

const base = { scene: "/farm/shot/scene.gltf", output: "/farm/out/frame_{frame}.exr", frames: "1-3", spp: 1024,
               chunks: 16, width: 1920, height: 1080, integrator: "pt", threads: 0, parts_dir: "", extra_args: "",
               veach: "/opt/veach/bin/veach" };

function valueAfter(args, flag) {
    const i = args.indexOf(flag);
    assert.ok(i >= 0 && i + 1 < args.length, `${flag} missing from ${args.join(" ")}`);
    return args[i + 1];
}

test("the job type declares the settings compileJob reads, with the types Flamenco knows", () => {
    const { jobType } = compile(base);
    const keys = jobType.settings.map((s) => s.key);
    for (const k of Object.keys(base)) assert.ok(keys.includes(k), `setting ${k} is not declared`);
    for (const s of jobType.settings) assert.ok(["string", "int32", "float", "bool"].includes(s.type), s.key);
    assert.strictEqual(typeof jobType.label, "string");
});

test("frames x chunks render tasks whose sample ranges tile [0, spp) exactly", () => {
    const { tasks } = compile(base);
    const renders = tasks.filter((t) => t.name.startsWith("render-"));
    assert.strictEqual(renders.length, 3 * 16);
    for (const frame of [1, 2, 3]) {
        const mine = renders.filter((t) => valueAfter(t.commands[0].parameters.args, "--frame") === String(frame));
        assert.strictEqual(mine.length, 16);
        const ranges = mine.map((t) => valueAfter(t.commands[0].parameters.args, "--samples").split(":").map(Number))
            .sort((x, y) => x[0] - y[0]);
        assert.strictEqual(ranges[0][0], 0);
        for (let i = 1; i < ranges.length; i++) assert.strictEqual(ranges[i][0], ranges[i - 1][1], "gap or overlap");
        assert.strictEqual(ranges[ranges.length - 1][1], 1024);
        for (const r of ranges) assert.strictEqual(r[1] - r[0], 64);
    }
    for (const t of renders) {
        assert.strictEqual(t.type, "veach");
        assert.strictEqual(t.commands.length, 1);
        const c = t.commands[0];
        assert.strictEqual(c.name, "exec");
        assert.strictEqual(c.parameters.exe, "/opt/veach/bin/veach");
        const args = c.parameters.args;
        assert.ok(args.every((a) => typeof a === "string"), "exec args must be strings");
        assert.strictEqual(args[0], "render");
        assert.strictEqual(args[1], base.scene);
        assert.strictEqual(valueAfter(args, "--spp"), "1024");
        assert.strictEqual(valueAfter(args, "--width"), "1920");
        assert.strictEqual(valueAfter(args, "--height"), "1080");
        assert.strictEqual(valueAfter(args, "--integrator"), "pt");
        assert.ok(args.includes("--resume") && args.includes("--skip-existing"));
        assert.ok(!args.includes("--threads"), "threads 0 must leave the default (the CPUs the task may use)");
        const out = valueAfter(args, "-o");
        assert.ok(out.startsWith("/farm/out/parts/") && out.endsWith(".vpart"), out);
    }
    const outs = renders.map((t) => valueAfter(t.commands[0].parameters.args, "-o"));
    assert.strictEqual(new Set(outs).size, outs.length, "two tasks write the same part");
});

test("one merge per frame: that frame's parts, --expect-spp, its output, its render tasks as dependencies", () => {
    const { tasks } = compile(base);
    const merges = tasks.filter((t) => t.name.startsWith("merge-"));
    assert.strictEqual(merges.length, 3);
    for (const m of merges) {
        const args = m.commands[0].parameters.args;
        assert.strictEqual(m.commands[0].name, "exec");
        assert.strictEqual(args[0], "merge");
        const frame = m.name.replace("merge-f", "");
        assert.strictEqual(valueAfter(args, "-o"), `/farm/out/frame_${frame}.exr`);
        assert.strictEqual(valueAfter(args, "--expect-spp"), "1024");
        const parts = args.filter((a) => a.endsWith(".vpart"));
        const deps = m.dependencies;
        assert.strictEqual(deps.length, 16);
        const depParts = deps.map((d) => valueAfter(d.commands[0].parameters.args, "-o"));
        assert.deepStrictEqual([...parts].sort(), [...depParts].sort());
        for (const d of deps) assert.strictEqual(valueAfter(d.commands[0].parameters.args, "--frame"), frame);
        // Dependencies must be tasks added to the job before or after, but added.
        for (const d of deps) assert.ok(tasks.includes(d));
    }
});

test("uneven chunks, a frame list, extra flags, threads and a parts folder", () => {
    const { tasks } = compile({ ...base, frames: "5,9..10", spp: 10, chunks: 3, threads: 4, extra_args: "--seed 3  --max-depth 8",
                                parts_dir: "/scratch/p", height: 0 });
    const renders = tasks.filter((t) => t.name.startsWith("render-"));
    assert.deepStrictEqual([...new Set(renders.map((t) => valueAfter(t.commands[0].parameters.args, "--frame")))],
                           ["5", "9", "10"]);
    const ranges = renders.filter((t) => valueAfter(t.commands[0].parameters.args, "--frame") === "9")
        .map((t) => valueAfter(t.commands[0].parameters.args, "--samples"));
    assert.deepStrictEqual(ranges, ["0:3", "3:6", "6:10"]);
    const args = renders[0].commands[0].parameters.args;
    assert.strictEqual(valueAfter(args, "--threads"), "4");
    assert.strictEqual(valueAfter(args, "--seed"), "3");
    assert.strictEqual(valueAfter(args, "--max-depth"), "8");
    assert.ok(!args.includes(""), "an empty argument from doubled spaces");
    assert.ok(!args.includes("--height"), "height 0 must leave the camera's aspect");
    assert.ok(valueAfter(args, "-o").startsWith("/scratch/p/scene_f5_"));
});

test("#### in the output is the frame zero-padded to the run's length, as veach render --frames writes it", () => {
    const { tasks } = compile({ ...base, frames: "7,12", output: "/farm/out/####/beauty_##.exr" });
    const outs = tasks.filter((t) => t.name.startsWith("merge-")).map((m) => valueAfter(m.commands[0].parameters.args, "-o"));
    assert.deepStrictEqual(outs, ["/farm/out/0007/beauty_07.exr", "/farm/out/0012/beauty_12.exr"]);
    assert.deepStrictEqual(compile({ ...base, frames: "123", output: "/farm/f_{frame}_#.exr" }).tasks
        .filter((t) => t.name.startsWith("merge-")).map((m) => valueAfter(m.commands[0].parameters.args, "-o")),
                           ["/farm/f_123_123.exr"]);
});

test("bad settings are refused when the job is compiled", () => {
    assert.throws(() => compile({ ...base, chunks: 2048 }), /chunks/);
    assert.throws(() => compile({ ...base, chunks: 0 }), /chunks/);
    assert.throws(() => compile({ ...base, spp: "many" }), /spp/);
    assert.throws(() => compile({ ...base, output: "/farm/out/still.exr" }), /\{frame\} or ####/);
    assert.throws(() => compile({ ...base, frames: "a-b" }));
    // One frame needs no {frame}.
    assert.strictEqual(compile({ ...base, frames: "7", output: "/farm/out/still.exr" }).tasks.length, 17);
});
