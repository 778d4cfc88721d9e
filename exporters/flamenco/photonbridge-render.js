// SPDX-License-Identifier: GPL-3.0-or-later
//
// Flamenco 3 job type: a frame range rendered by `photonbridge render` on the
// farm's workers. Install: copy this file into the `scripts/`
// folder beside the flamenco-manager executable and restart the manager
// (docs/farms.md). Workers run the `exec` command (task type
// "misc"), so they need photonbridge on their PATH (or the manager variable
// named in the "photonbridge" setting) and the scene and output on shared
// storage.
//
// Chunking: Flamenco's frameChunker() cuts the frame list into chunks of at
// most chunk_size frames, each written as comma-separated runs ("1-10",
// "9,10,20,21"). photonbridge renders one contiguous range per process, so
// every chunk becomes one task with one `exec` command per contiguous run,
// and every run first renders `warmup` frames before its first frame
// (`--warmup`, not written) to rebuild the temporal filter's history. The
// photon seeds follow the frame number, so a frame comes out as it would in
// one run of the whole shot up to the history older than the warm-up
// (docs/farms.md measures how many frames make the boundary
// invisible: 32 frames, the default).

const JOB_TYPE = {
    label: "photonbridge Render",
    description: "Render a frame range of a glTF scene with photonbridge (GPU photon mapping), in chunks with warm-up",
    settings: [
        { key: "photonbridge", type: "string", default: "photonbridge", visible: "submission",
          description: "photonbridge executable on the workers (a name on PATH, a path, or a manager variable such as {photonbridge})" },
        { key: "scene", type: "string", subtype: "file_path", required: true,
          description: "Scene on shared storage: a .gltf/.glb from the photonbridge Blender exporter" },
        { key: "frames", type: "string", required: true, eval: "f'{C.scene.frame_start}-{C.scene.frame_end}'",
          description: "Frames to render. Examples: '47', '1-30', '3, 5-10, 47-327'" },
        { key: "chunk_size", type: "int32", default: 32, propargs: { min: 1 }, visible: "submission",
          description: "Frames per task" },
        { key: "warmup", type: "int32", default: 32, propargs: { min: 0, max: 10000 }, visible: "submission",
          description: "Frames rendered before each run (not written) to rebuild the temporal history" },
        { key: "fps", type: "float", eval: "C.scene.render.fps / C.scene.render.fps_base", visible: "submission",
          description: "Frames per second: frame f is the scene at time f/fps" },
        { key: "render_output_path", type: "string", subtype: "file_path", required: true,
          description: "Output EXR per frame; a run of '#' is the frame number (//render/shot_######.exr)" },
        { key: "width", type: "int32", default: 0, visible: "submission", description: "Width in pixels (0: the scene's)" },
        { key: "height", type: "int32", default: 0, visible: "submission", description: "Height in pixels (0: the scene's)" },
        { key: "photons", type: "int32", default: 0, visible: "submission", description: "Photons per frame (0: default)" },
        { key: "seed", type: "int32", default: 0, visible: "submission", description: "Base seed (0: default); frame f mixes in f" },
        { key: "extra_args", type: "string", default: "", visible: "submission",
          description: "More photonbridge render options, separated by spaces" },
    ]
};

function compileJob(job) {
    const s = job.settings;
    const output = String(s.render_output_path || "");
    if (!s.scene) throw "photonbridge-render: the scene setting is empty";
    if (output.indexOf("#") < 0)
        throw `photonbridge-render: render_output_path '${output}' needs a run of '#' for the frame number`;
    const chunkSize = s.chunk_size === undefined ? 32 : s.chunk_size;
    const warmup = s.warmup === undefined ? 32 : s.warmup;
    if (!(chunkSize >= 1)) throw `photonbridge-render: chunk_size ${chunkSize} must be at least 1`;
    if (!(warmup >= 0)) throw `photonbridge-render: warmup ${warmup} must not be negative`;

    let runs = 0;
    for (const chunk of frameChunker(String(s.frames), chunkSize)) {
        const task = author.Task(`render-${chunk}`, "misc");
        for (const run of contiguousRuns(chunk)) {
            runs++;
            task.addCommand(author.Command("exec", {
                exe: s.photonbridge || "photonbridge",
                args: renderArgs(s, output, run, warmup),
            }));
        }
        job.addTask(task);
    }
    // frameCount() where the manager has it (newer Flamenco 3 releases).
    if (typeof frameCount === "function")
        print(`photonbridge-render: ${frameCount(String(s.frames))} frames in ${runs} runs, ` +
              `${runs * warmup} warm-up frames rendered besides`);
}

// The photonbridge command line of one contiguous run [first, last].
function renderArgs(s, output, run, warmup) {
    const args = ["render", s.scene, "--frames", `${run[0]}:${run[1]}`, "--warmup", String(warmup),
                  "-o", output, "-q"];
    if (s.fps) args.push("--fps", String(s.fps));
    if (s.width > 0) args.push("--width", String(s.width));
    if (s.height > 0) args.push("--height", String(s.height));
    if (s.photons > 0) args.push("--photons", String(s.photons));
    if (s.seed > 0) args.push("--seed", String(s.seed));
    const extra = String(s.extra_args || "").trim();
    if (extra) args.push(...extra.split(/\s+/));
    return args;
}

// A chunk from frameChunker ("1-10", "9,10,20,21", "3,5-7"; Blender's ".."
// too) as sorted contiguous runs [[first, last], ...]. Frame numbers are
// non-negative, as in Flamenco's own notation.
function contiguousRuns(chunk) {
    const frames = [];
    for (const part of String(chunk).replace(/\.\./g, "-").split(",")) {
        const p = part.trim();
        if (!p) continue;
        const m = /^(\d+)(?:\s*-\s*(\d+))?$/.exec(p);
        if (!m) throw `photonbridge-render: cannot read the frames '${p}' of chunk '${chunk}'`;
        const a = parseInt(m[1], 10), b = m[2] === undefined ? a : parseInt(m[2], 10);
        if (b < a) throw `photonbridge-render: frames '${p}' run backwards`;
        for (let f = a; f <= b; ++f) frames.push(f);
    }
    frames.sort((x, y) => x - y);
    const runs = [];
    for (const f of frames) {
        const last = runs[runs.length - 1];
        if (last && f === last[1]) continue;
        if (last && f === last[1] + 1) last[1] = f;
        else runs.push([f, f]);
    }
    return runs;
}
