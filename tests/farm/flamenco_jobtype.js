// The Flamenco 3 job type exporters/flamenco/photonbridge-render.js compiled
// in node against a stub of the manager's globals: author.Task,
// author.Command, frameChunker (as Flamenco's js_globals.go chunks: sorted,
// deduplicated frames, chunks of chunk_size frames written as merged runs,
// two-frame runs as "a,b"), frameCount, print. Checks the tasks and their exec commands
// for several frame ranges and chunk sizes, non-contiguous chunks included,
// and the errors for bad settings.
//
// usage: node flamenco_jobtype.js ROOT
"use strict";
const fs = require("fs");
const path = require("path");
const vm = require("vm");

const ROOT = process.argv[2] || path.join(__dirname, "..", "..");
const SOURCE = fs.readFileSync(path.join(ROOT, "exporters/flamenco/photonbridge-render.js"), "utf8");
let failures = 0;

function check(cond, what) {
  console.log((cond ? "ok   " : "FAIL ") + what);
  if (!cond) failures++;
}

// ---- the stub of the manager's globals -----------------------------------
function explode(range) {
  const set = new Set();
  for (const part of range.replace(/\.\./g, "-").split(",")) {
    const se = part.split("-");
    if (se.length === 1) set.add(parseInt(se[0].trim(), 10));
    else if (se.length === 2) {
      const a = parseInt(se[0].trim(), 10), b = parseInt(se[1].trim(), 10);
      for (let f = a; f <= b; ++f) set.add(f);
    } else throw `invalid range "${range}"`;
  }
  if ([...set].some(Number.isNaN)) throw `invalid range "${range}"`;
  return [...set].sort((x, y) => x - y);
}
function merge(frames) {
  const out = [];
  let start = frames[0], prev = frames[0];
  const flush = (a, b) => {
    if (a === b) out.push(String(a));
    else if (a + 1 === b) out.push(String(a), String(b));
    else out.push(`${a}-${b}`);
  };
  for (const f of frames.slice(1)) {
    if (f > prev + 1) { flush(start, prev); start = f; }
    prev = f;
  }
  flush(start, prev);
  return out.join(",");
}
function frameChunker(range, size) {
  range = String(range).trim();
  if (!range) throw "empty range";
  if (size < 1) throw `invalid chunk size, must be positive number: ${size}`;
  const frames = explode(range), chunks = [];
  for (let i = 0; i < frames.length; i += size) chunks.push(merge(frames.slice(i, i + size)));
  return chunks;
}

let printed = [];
function compile(settings) {
  const tasks = [];
  printed = [];
  const ctx = {
    print: (...a) => printed.push(a.join(" ")),
    frameChunker,
    frameCount: (r) => explode(String(r)).length,
    author: {
      Task: (name, type) => ({ name, type, commands: [], deps: [],
                                addCommand(c) { this.commands.push(c); },
                                addDependency(t) { this.deps.push(t); } }),
      Command: (name, parameters) => ({ name, parameters }),
    },
  };
  vm.createContext(ctx);
  vm.runInContext(SOURCE + "\n;this.JOB_TYPE = JOB_TYPE;", ctx, { filename: "photonbridge-render.js" });
  const job = { name: "shot", settings: Object.assign({}, settings), addTask: (t) => tasks.push(t) };
  ctx.compileJob(job);
  return { tasks, jobType: ctx.JOB_TYPE };
}

const BASE = { photonbridge: "/opt/pb/photonbridge", scene: "/farm/shot/scene.gltf",
               render_output_path: "/farm/shot/out/f_####.exr" };

// Every case: settings, then the expected tasks as [name, [[first, last], ...]].
const CASES = [
  ["1-10 by 4", { frames: "1-10", chunk_size: 4, warmup: 2 },
   [["render-1-4", [[1, 4]]], ["render-5-8", [[5, 8]]], ["render-9,10", [[9, 10]]]]],
  ["9,10,20,21 by 4 (one task, two runs)", { frames: "9,10,20,21", chunk_size: 4, warmup: 3 },
   [["render-9,10,20,21", [[9, 10], [20, 21]]]]],
  ["9,10,20,21 by 3", { frames: "9,10,20,21", chunk_size: 3, warmup: 3 },
   [["render-9,10,20", [[9, 10], [20, 20]]], ["render-21", [[21, 21]]]]],
  ["'3, 5-10, 47' by 100", { frames: "3, 5-10, 47", chunk_size: 100, warmup: 0 },
   [["render-3,5-10,47", [[3, 3], [5, 10], [47, 47]]]]],
  ["1-3 by 1", { frames: "1-3", chunk_size: 1, warmup: 8 },
   [["render-1", [[1, 1]]], ["render-2", [[2, 2]]], ["render-3", [[3, 3]]]]],
  ["Blender's 1..5,7 by 6", { frames: "1..5,7", chunk_size: 6, warmup: 1 },
   [["render-1-5,7", [[1, 5], [7, 7]]]]],
];

for (const [what, settings, expected] of CASES) {
  let r;
  try {
    r = compile(Object.assign({}, BASE, settings));
  } catch (e) {
    check(false, `${what}: compiles (${e})`);
    continue;
  }
  const got = r.tasks.map((t) => [t.name, t.commands.map((c) => {
    const a = c.parameters.args, i = a.indexOf("--frames");
    return a[i + 1].split(":").map(Number);
  })]);
  check(JSON.stringify(got) === JSON.stringify(expected),
        `${what}: tasks ${JSON.stringify(got)}`);
  const runs = expected.reduce((n, t) => n + t[1].length, 0);
  const frames = expected.reduce((n, t) => n + t[1].reduce((m, r) => m + r[1] - r[0] + 1, 0), 0);
  check(printed.some((l) => l.indexOf(`${frames} frames in ${runs} runs, ${runs * settings.warmup} warm-up`) >= 0),
        `${what}: the log line counts ${frames} frames, ${runs} runs (${printed.join(" | ")})`);
  const warm = String(settings.warmup);
  check(r.tasks.every((t) => t.type === "misc" && t.commands.every((c) =>
          c.name === "exec" && c.parameters.exe === BASE.photonbridge &&
          c.parameters.args[0] === "render" && c.parameters.args[1] === BASE.scene &&
          c.parameters.args[c.parameters.args.indexOf("--warmup") + 1] === warm &&
          c.parameters.args[c.parameters.args.indexOf("-o") + 1] === BASE.render_output_path)),
        `${what}: every command is exec photonbridge render SCENE ... --warmup ${warm} -o OUT`);
}

// One command line in full, with the optional settings.
{
  const r = compile(Object.assign({}, BASE, { frames: "12-15", chunk_size: 10, warmup: 4, fps: 25, width: 64,
                                              height: 48, photons: 8192, seed: 7,
                                              extra_args: " --no-temporal  --atrous-iterations 2 " }));
  const args = r.tasks.length === 1 && r.tasks[0].commands.length === 1 ? r.tasks[0].commands[0].parameters.args : [];
  const want = ["render", BASE.scene, "--frames", "12:15", "--warmup", "4", "-o", BASE.render_output_path, "-q",
                "--fps", "25", "--width", "64", "--height", "48", "--photons", "8192", "--seed", "7",
                "--no-temporal", "--atrous-iterations", "2"];
  check(JSON.stringify(args) === JSON.stringify(want), `the full command line: ${JSON.stringify(args)}`);
  check(Array.isArray(r.jobType.settings) && r.jobType.settings.some((x) => x.key === "warmup") &&
        r.jobType.settings.some((x) => x.key === "chunk_size"), "JOB_TYPE declares chunk_size and warmup");
}

// Bad settings: compileJob throws a message naming the setting.
for (const [what, settings, needle] of [
  ["output without '#'", { frames: "1-4", render_output_path: "/farm/out/f.exr" }, "render_output_path"],
  ["chunk_size 0", { frames: "1-4", chunk_size: 0 }, "chunk_size"],
  ["negative warmup", { frames: "1-4", warmup: -1 }, "warmup"],
  ["no scene", { frames: "1-4", scene: "" }, "scene"],
]) {
  let msg = null;
  try {
    compile(Object.assign({}, BASE, settings));
  } catch (e) {
    msg = String(e);
  }
  check(msg !== null && msg.indexOf(needle) >= 0, `${what}: rejected (${msg})`);
}

if (failures) {
  console.log(`${failures} check(s) failed`);
  process.exit(1);
}
console.log("all checks passed");
