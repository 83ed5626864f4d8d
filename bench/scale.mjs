#!/usr/bin/env node
// Opening large OBJ files (issue 14): the spiky ball subdivided to N = 10k ... 2.6M vertices
// (`mrvol subdivide`, cached in .cache/scale/, outside git), opened as `mrvol info` does (readObj
// of the file's bytes + openMesh: validation and hierarchy detection + info) in our WASM module,
// beside three.js OBJLoader's parse() of the same text. Each measurement runs in a fresh Node
// process so that its peak memory (max RSS, and the WASM heap's size) is its own.
// Goals: 655k opened in at most half OBJLoader's time; 2.6M in <= 5 s; peak <= 300 bytes per vertex.
// Then drag steps on the large meshes (step + the renderer's positions and normals): goals <= 16 ms
// at 655k, <= 60 ms at 2.6M.
// Writes bench/RESULTS-scale.md (machine, date) unless --no-write.
//
//   node bench/scale.mjs [--no-write] [--quick] [--open-only | --edit-only]
//   (--quick: up to 163k; a run of one part keeps the other's section of the results file)
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, statSync, writeFileSync } from 'node:fs';
import { cpus, loadavg, totalmem } from 'node:os';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('..', import.meta.url));
const cacheDir = `${root}.cache/scale`;
const LEVELS = { 10242: 2, 40962: 3, 163842: 4, 655362: 5, 2621442: 6 };  // subdivisions of the 642-vertex ball
const roundsFor = (n) => (n <= 163842 ? 3 : n <= 655362 ? 2 : 1);

// CPU time (user + system) between two process.cpuUsage() readings: on a shared machine the
// fair measure (wall time counts the other processes' turns too).
const cpuMs = (a, b) => (b.user - a.user + b.system - a.system) / 1000;

// ---- child: one measurement ---------------------------------------------------------------------
async function child(kind, path) {
  const result = {};
  if (kind === 'mrvol') {
    const { wrapModule } = await import('../lib/api.mjs');
    const { readObjFile } = await import('../lib/node.mjs');
    const buildDir = new URL('../build/wasm/', import.meta.url);
    const { default: factory } = await import(new URL('mrvol-node.mjs', buildDir).href);
    const raw = await factory({ wasmBinary: readFileSync(new URL('mrvol-node.wasm', buildDir)) });
    const mrvol = wrapModule(raw);
    // As `mrvol info` reads it: the file in chunks straight into the WASM reader (the read's
    // CPU time includes the file reads).
    const c0 = process.cpuUsage(), t0 = performance.now();
    const mesh = await readObjFile(mrvol, path);
    const c1 = process.cpuUsage(), t1 = performance.now();
    const mr = mrvol.openMesh(mesh);
    const info = mr.info();
    const c2 = process.cpuUsage(), t2 = performance.now();
    mr.delete();
    Object.assign(result, { readMs: t1 - t0, openMs: t2 - t1, totalMs: t2 - t0, readCpuMs: cpuMs(c0, c1),
                            openCpuMs: cpuMs(c1, c2), cpuMs: cpuMs(c0, c2), levels: info.levels,
                            vertices: info.vertices, wasmHeap: raw.HEAPU8.length });
  } else if (kind === 'edit') {
    Object.assign(result, await editSteps(readFileSync(path), Number(process.argv[5] ?? 1)));
  } else {
    const bytes = readFileSync(path);
    const { OBJLoader } = await import('three/examples/jsm/loaders/OBJLoader.js');
    const text = bytes.toString('utf8');
    const c0 = process.cpuUsage(), t0 = performance.now();
    const group = new OBJLoader().parse(text);
    const c1 = process.cpuUsage(), t1 = performance.now();
    result.totalMs = t1 - t0;
    result.cpuMs = cpuMs(c0, c1);
    result.vertices = group.children[0].geometry.attributes.position.count;  // 3 per triangle
  }
  result.maxRss = process.resourceUsage().maxRSS * 1024;
  process.stdout.write(JSON.stringify(result) + '\n');
}

// Drag steps at each editing level: a held cage vertex moved a little at a time (as a pointer drag
// does), each step timed as the app sees it: the step (moveVertices: the cage move and the volume
// correction), then the renderer's buffers (positionsView, normalsView). CPU time and wall time per
// part, medians over the steps after warm-up ones. The process runs with --no-liftoff: every WASM
// function is compiled by the optimizing tier up front, as the app's hot loops are after their first
// frames in Chromium; with Node's default dynamic tiering the first steps run baseline code and V8's
// background tier-up (and its compile threads' CPU time, counted by process.cpuUsage) lands inside
// the timed steps.
const EDIT_LEVELS = [0, 3, 5];
const EDIT_HEADING = '# Drag steps on large meshes (bench/scale.mjs)';
const EDIT_STEPS = 20, EDIT_WARMUP = 10;
const EDIT_THREADS = Math.max(2, Math.min(8, cpus().length));  // the threaded rows': the cores (at least 2)
// threads: 1, the single-thread module; more, the threaded one (mrvol-node-mt) on that many.
async function editSteps(bytes, threads) {
  const { createMrvol } = await import('../lib/node.mjs');
  const mrvol = await createMrvol({ threads });
  if (mrvol.threads !== threads) throw new Error(`asked for ${threads} threads, got ${mrvol.threads}`);
  const mr = mrvol.openMesh(mrvol.readObj(bytes));
  const median = (a) => [...a].sort((x, y) => x - y)[a.length >> 1];
  const levels = {};
  const load = [loadavg()[0]];
  for (const level of EDIT_LEVELS) {
    const c0 = process.cpuUsage(), t0 = performance.now();
    const ed = mr.createEditor({ level });
    const setupCpuMs = cpuMs(c0, process.cpuUsage()), setupWallMs = performance.now() - t0;
    ed.normalsView();
    const vertex = ed.cageVertices()[1];
    // Steps of 0.5% of the mesh's size: a pointer drag's frame.
    const size = ed.cagePositions().reduce((m, x) => Math.max(m, Math.abs(x)), 0);
    const offset = [0.005 * size, 0.0025 * size, 0];
    // The frame as the app draws it (web/surface-upload.js): normalsView() first (positions and
    // normals in one pass), then positionsView() (already current).
    const parts = { step: [], surface: [] };
    const wall = { step: [], surface: [] };
    let worst = 0, corrected = 0;
    for (let s = 0; s < EDIT_WARMUP + EDIT_STEPS; ++s) {
      const a = process.cpuUsage(), ta = performance.now();
      const report = ed.moveVertices([{ vertex, offset }]);
      const b = process.cpuUsage(), tb = performance.now();
      ed.normalsView();
      ed.positionsView();
      const c = process.cpuUsage(), tc = performance.now();
      if (!report.converged) throw new Error(`level ${level}: ${report.message}`);
      worst = Math.max(worst, report.relativeError);
      if (s < EDIT_WARMUP) continue;
      if (report.iterations > 0) ++corrected;
      parts.step.push(cpuMs(a, b)), parts.surface.push(cpuMs(b, c));
      wall.step.push(tb - ta), wall.surface.push(tc - tb);
    }
    // The parts apart: positionsView() alone, then normalsView() (10 more steps).
    const split = { positions: [], normals: [] };
    for (let s = 0; s < 10; ++s) {
      ed.moveVertices([{ vertex, offset }]);
      const a = process.cpuUsage();
      ed.positionsView();
      const b = process.cpuUsage();
      ed.normalsView();
      split.positions.push(cpuMs(a, b)), split.normals.push(cpuMs(b, process.cpuUsage()));
    }
    // The frame under flat shading (the app's default: three.js derives each face's normal in the
    // fragment shader, so no normals are computed on the CPU): step + positionsView(), 20 more steps.
    const flat = [];
    for (let s = 0; s < EDIT_STEPS; ++s) {
      const a = process.cpuUsage();
      ed.moveVertices([{ vertex, offset }]);
      ed.positionsView();
      flat.push(cpuMs(a, process.cpuUsage()));
    }
    // The same drag with a tolerance of 1e-10: every step corrects the volume over the whole free
    // set (at e = 5 the default tolerance lets most steps pass uncorrected), and the positions then
    // follow a move of the whole cage.
    const correcting = { step: [], positions: [], stepWall: [], positionsWall: [] };
    for (let s = 0; s < 10; ++s) {
      const a = process.cpuUsage(), ta = performance.now();
      const report = ed.moveVertices([{ vertex, offset }], { tolerance: 1e-10 });
      const b = process.cpuUsage(), tb = performance.now();
      ed.positionsView();
      correcting.step.push(cpuMs(a, b)), correcting.positions.push(cpuMs(b, process.cpuUsage()));
      correcting.stepWall.push(tb - ta), correcting.positionsWall.push(performance.now() - tb);
      if (!report.converged || report.iterations === 0) throw new Error(`level ${level}: no correction ran`);
    }
    levels[level] = { path: ed.path(), cage: ed.cageSize, setupCpuMs, setupWallMs, stepMs: median(parts.step),
                      surfaceMs: median(parts.surface), positionsMs: median(split.positions), normalsMs: median(split.normals),
                      frameMs: median(parts.step.map((x, i) => x + parts.surface[i])), flatFrameMs: median(flat),
                      fastestFrameMs: Math.min(...parts.step.map((x, i) => x + parts.surface[i])), worst,
                      corrected, correctMs: median(correcting.step), correctPositionsMs: median(correcting.positions),
                      wall: { stepMs: median(wall.step), surfaceMs: median(wall.surface),
                              frameMs: median(wall.step.map((x, i) => x + wall.surface[i])),
                              correctMs: median(correcting.stepWall), correctPositionsMs: median(correcting.positionsWall) } };
    ed.delete();
    load.push(loadavg()[0]);
  }
  mr.delete();
  return { levels, load };
}

if (process.argv[2] === '--child') {
  await child(process.argv[3], process.argv[4]);
  process.exit(0);
}

// ---- parent ---------------------------------------------------------------------------------------
const write = !process.argv.includes('--no-write');
const quick = process.argv.includes('--quick');
mkdirSync(cacheDir, { recursive: true });

function meshFile(n) {
  const path = `${cacheDir}/spiky-L${LEVELS[n]}.obj`;
  if (!existsSync(path)) {
    process.stderr.write(`bench: making ${path}\n`);
    execFileSync(process.execPath, [`${root}bin/mrvol.mjs`, 'subdivide', `${root}public/models/spiky-ball.obj`,
                                    '--levels', String(LEVELS[n]), '-o', path], { stdio: 'inherit' });
  }
  return path;
}

function measure(kind, path, threads = 1) {
  const flags = ['--max-old-space-size=8192', ...(kind === 'edit' ? ['--no-liftoff'] : [])];
  const out = execFileSync(process.execPath, [...flags, fileURLToPath(import.meta.url), '--child', kind, path, String(threads)],
                           { encoding: 'utf8', maxBuffer: 1 << 20 });
  return JSON.parse(out.trim().split('\n').pop());
}

// Lowest CPU time of a few fresh processes (the machine is shared); memory from the same runs (max).
function best(kind, path, rounds) {
  const runs = Array.from({ length: rounds }, () => measure(kind, path));
  const fastest = runs.reduce((a, b) => (b.cpuMs < a.cpuMs ? b : a));
  return { ...fastest, maxRss: Math.max(...runs.map((r) => r.maxRss)) };
}

const sizes = Object.keys(LEVELS).map(Number).filter((n) => !quick || n <= 163842);
const onlyEdit = process.argv.includes('--edit-only'), onlyOpen = process.argv.includes('--open-only');
const rows = [];
for (const n of onlyEdit ? [] : sizes) {
  const path = meshFile(n);
  const bytes = statSync(path).size;
  const ours = best('mrvol', path, roundsFor(n));
  const three = best('three', path, roundsFor(n));
  if (ours.vertices !== n) throw new Error(`${path}: read ${ours.vertices} vertices, expected ${n}`);
  rows.push({ n, bytes, ours, three });
  process.stderr.write(`bench: N = ${n}: ours ${ours.cpuMs.toFixed(0)} ms CPU (read ${ours.readCpuMs.toFixed(0)}, ` +
                       `open ${ours.openCpuMs.toFixed(0)}; wall ${ours.totalMs.toFixed(0)}), OBJLoader ${three.cpuMs.toFixed(0)} ms CPU ` +
                       `(wall ${three.totalMs.toFixed(0)}), ` +
                       `RSS ${(ours.maxRss / n).toFixed(0)} B/vertex\n`);
}
// Editing: the large meshes only (one process each: it opens the mesh once for every level), on
// the single-thread module and on the threaded one with EDIT_THREADS threads (when it is built).
const threadCounts = [1, ...(existsSync(`${root}build/wasm/mrvol-node-mt.mjs`) ? [EDIT_THREADS] : [])];
const editRows = [];
for (const n of onlyOpen ? [] : sizes.filter((n) => n >= (quick ? 40962 : 655362))) for (const threads of threadCounts) {
  const r = measure('edit', meshFile(n), threads);
  for (const [level, m] of Object.entries(r.levels)) {
    editRows.push({ n, level: Number(level), threads, load: r.load, ...m });
    process.stderr.write(`bench: N = ${n}, e = ${level}, ${threads} thread(s) (${m.path}, cage ${m.cage}): step ${m.stepMs.toFixed(2)} ms, ` +
                         `surface ${m.surfaceMs.toFixed(2)} (apart: positions ${m.positionsMs.toFixed(2)}, normals ${m.normalsMs.toFixed(2)}), ` +
                         `frame ${m.frameMs.toFixed(2)} ms CPU, flat-shaded ${m.flatFrameMs.toFixed(2)} (wall ${m.wall.stepMs.toFixed(2)}, ${m.wall.surfaceMs.toFixed(2)}, ` +
                         `frame ${m.wall.frameMs.toFixed(2)}); load ${r.load.map((x) => x.toFixed(1)).join(' -> ')}\n`);
  }
}

editRows.sort((a, b) => a.n - b.n || a.level - b.level || a.threads - b.threads);  // st and mt rows side by side
const f0 = (x) => x.toFixed(0);
const f1 = (x) => x.toFixed(1);
const mb = (x) => (x / 1e6).toFixed(1);
const goal655 = rows.find((r) => r.n === 655362);
const goal26 = rows.find((r) => r.n === 2621442);
const verdict = (ok) => (ok ? 'met' : '**not met**');
const machine = [
  `Machine: ${cpus()[0]?.model ?? 'unknown CPU'} x ${cpus().length}, ${(totalmem() / 2 ** 30).toFixed(0)} GB; ` +
    `Node ${process.version}; load average ${loadavg()[0].toFixed(1)} at the end.`,
  `Date: ${new Date().toISOString()}`,
];
const openSection = [
  '# Opening large OBJ files (bench/scale.mjs)',
  '',
  ...machine,
  '',
  'Meshes: public/models/spiky-ball.obj subdivided with `mrvol subdivide` (Loop), cached in .cache/scale/.',
  'Ours: readObjFile (lib/node.mjs: the file read in 16 MB chunks straight into the WASM OBJ reader) + openMesh',
  '(validation, hierarchy detection) + info(), the WASM module under Node, as `mrvol info` does.',
  "three.js: OBJLoader.parse(text) of the same file (text already decoded). Times are CPU time (user + system, the",
  'lowest of 3 fresh processes up to 163k, 2 at 655k, 1 at 2.6M): the machine is shared, and wall time counts the',
  "other processes' turns (wall times beside). Peak memory: the process's max RSS (Node itself included; ours",
  "never holds the whole file, OBJLoader's run holds its text), and the WASM heap at the end (it never shrinks, so it is its peak).",
  '',
  '| vertices | file MB | read ms | read MB/s | open ms | total ms | OBJLoader ms | ours / OBJLoader | wall: ours, OBJLoader ms | levels | max RSS MB | RSS B/vertex | WASM heap MB | heap B/vertex | OBJLoader RSS MB |',
  '| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |',
  ...rows.map(({ n, bytes, ours, three }) =>
    `| ${n} | ${mb(bytes)} | ${f0(ours.readCpuMs)} | ${f0(bytes / 1e3 / ours.readCpuMs)} | ${f0(ours.openCpuMs)} | ${f0(ours.cpuMs)} | ` +
    `${f0(three.cpuMs)} | ${(ours.cpuMs / three.cpuMs).toFixed(2)} | ${f0(ours.totalMs)}, ${f0(three.totalMs)} | ${ours.levels} | ${mb(ours.maxRss)} | ` +
    `${f0(ours.maxRss / n)} | ${mb(ours.wasmHeap)} | ${f0(ours.wasmHeap / n)} | ${mb(three.maxRss)} |`),
  '',
  'Goals:',
  goal655 ? `- 655k opened in at most half OBJLoader's time: ${f0(goal655.ours.cpuMs)} ms vs ${f0(goal655.three.cpuMs)} ms CPU ` +
            `(ratio ${(goal655.ours.cpuMs / goal655.three.cpuMs).toFixed(2)}): ${verdict(goal655.ours.cpuMs <= goal655.three.cpuMs / 2)}` : '- 655k: not run (--quick)',
  goal26 ? `- 2.6M opened in <= 5 s: ${f0(goal26.ours.cpuMs)} ms CPU: ${verdict(goal26.ours.cpuMs <= 5000)}` : '- 2.6M: not run (--quick)',
  goal26 ? `- peak memory <= 300 bytes per vertex at 2.6M: ${f0(goal26.ours.maxRss / goal26.n)} B/vertex (max RSS): ${verdict(goal26.ours.maxRss / goal26.n <= 300)}` : '',
  '',
].join('\n');
const frameGoal = (n) => (n <= 655362 ? 16 : 60);
// A frame's time against its goal: CPU time on one thread; wall time on several (CPU time sums them).
const judged = (r) => (r.threads === 1 ? r.frameMs : r.wall.frameMs);
const editSection = [
  EDIT_HEADING,
  '',
  ...machine,
  '',
  'The same meshes, opened once per process; an editor at level e (cage of V_e vertices; the path `auto` picks).',
  `Drag: a held cage vertex moved by ${EDIT_STEPS} steps of 0.5% of the mesh's size (after ${EDIT_WARMUP} warm-up ones), each step`,
  'timed as the app sees it. Step: moveVertices (cage move and, when the volume left the tolerance, the correction;',
  "steps corrected says how many needed one); surface: normalsView() then positionsView(), as the app asks for them",
  "(web/surface-upload.js: the fine positions, float32 in the caller's order, and area-weighted normals, in one pass).",
  'Flat-shaded frame: 20 more steps of step + positionsView() alone, the frame of flat shading (the app\'s default:',
  "three.js's flatShading derives each face's normal from screen-space derivatives in the fragment shader; no normals",
  'on the CPU). Apart: 10 more steps with positionsView() alone, then normalsView(). CPU time per part (user + system of',
  'the process), median over the steps; frame: the median of step + surface (fastest: the lowest of the 20, the cost with the',
  "least interference from other processes); wall: the same from performance.now() (it counts",
  "other processes' turns on a loaded machine). Node runs with --no-liftoff (every WASM function optimized before the",
  "first step, as the app's hot loops are after a few frames; no background tier-up in the timed steps). Correcting:",
  '10 more steps with tolerance 1e-10, so that each corrects the volume over the whole free set (step, and positions',
  "after it), medians. Set-up: createEditor (the path's precomputation; CPU time, and wall time beside: a threaded row's",
  'precomputation runs partly on the pool). Load: the 1-minute load average at the start and after each level.',
  'The hierarchy found in these files starts at 12 vertices: e = 3 is the 642-vertex spiky ball, e = 5 a cage of 10,242.',
  `Threads: 1 is the single-thread module (mrvol-node); ${EDIT_THREADS} the threaded one (mrvol-node-mt, WASM pthreads: the surface`,
  'passes and the cage basis table on that many threads), each in a process of its own, rows side by side. CPU time',
  "counts every thread's time, so a threaded row's CPU figures are the work, not the time a frame takes: for those",
  'rows the goal is judged on wall time (the frame as the user waits for it), which is fair only on a quiet machine (see load).',
  '',
  '| vertices | e | threads | cage | path | set-up ms | set-up wall ms | step ms | surface ms | frame ms | goal ms | fastest frame ms | flat-shaded frame ms | apart: positions, normals ms | wall: step, surface, frame ms | steps corrected | worst rel. volume error | correcting: step ms | positions ms | wall: step, positions ms | load |',
  '| ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |',
  ...editRows.map((r) => `| ${r.n} | ${r.level} | ${r.threads} | ${r.cage} | ${r.path} | ${f0(r.setupCpuMs)} | ${f0(r.setupWallMs)} | ${r.stepMs.toFixed(2)} | ` +
    `${r.surfaceMs.toFixed(2)} | ${f1(r.frameMs)} | ${frameGoal(r.n)} ${verdict(judged(r) <= frameGoal(r.n))} | ${f1(r.fastestFrameMs)} | ${f1(r.flatFrameMs)} | ` +
    `${r.positionsMs.toFixed(2)}, ${r.normalsMs.toFixed(2)} | ${r.wall.stepMs.toFixed(2)}, ${r.wall.surfaceMs.toFixed(2)}, ${f1(r.wall.frameMs)} | ` +
    `${r.corrected}/${EDIT_STEPS} | ${r.worst.toExponential(1)} | ${r.correctMs.toFixed(2)} | ${r.correctPositionsMs.toFixed(2)} | ` +
    `${r.wall.correctMs.toFixed(2)}, ${r.wall.correctPositionsMs.toFixed(2)} | ${r.load.map((x) => x.toFixed(1)).join(' -> ')} |`),
  '',
  'Goals:',
  ...editRows.filter((r) => r.level === 0 || (r.n === 655362 && r.level === 3)).map((r) => `- N = ${r.n}, e = ${r.level}, ${r.threads} thread(s): ` +
    `step + positions + normals <= ${frameGoal(r.n)} ms: ${f1(r.frameMs)} ms CPU (wall ${f1(r.wall.frameMs)}): ${verdict(judged(r) <= frameGoal(r.n))}` +
    (r.threads === 1 ? `; flat-shaded (normals in the fragment shader): ${f1(r.flatFrameMs)} ms CPU: ${verdict(r.flatFrameMs <= frameGoal(r.n))}` : '')),
  ...editRows.filter((r) => r.n === 655362 && r.level >= 3).map((r) => `- N = 655362, e = ${r.level} (cage ${r.cage}), ${r.threads} thread(s): a correcting ` +
    `step <= 16 ms: ${r.correctMs.toFixed(1)} ms CPU (wall ${r.wall.correctMs.toFixed(1)}; ${r.path}): ` +
    `${verdict((r.threads === 1 ? r.correctMs : r.wall.correctMs) <= 16)}`),
  ...editRows.filter((r) => r.level === 0).map((r) => `- N = ${r.n}, e = 0, ${r.threads} thread(s): a step alone <= 0.2 ms: ` +
    `${r.stepMs.toFixed(2)} ms CPU (wall ${r.wall.stepMs.toFixed(2)}): ${verdict((r.threads === 1 ? r.stepMs : r.wall.stepMs) <= 0.2)}`),
  ...editRows.filter((r) => r.n === 655362 && r.level === 0).map((r) => `- N = 655362, e = 0, ${r.threads} thread(s): editor set-up ` +
    `<= 1 s: ${f0(r.setupCpuMs)} ms CPU (wall ${f0(r.setupWallMs)}): ${verdict((r.threads === 1 ? r.setupCpuMs : r.setupWallMs) <= 1000)}`),
  '',
].join('\n');
const resultsPath = fileURLToPath(new URL('RESULTS-scale.md', import.meta.url));
// A run of one part keeps the other part's section from the file.
const previous = existsSync(resultsPath) ? readFileSync(resultsPath, 'utf8') : '';
const cut = previous.indexOf(EDIT_HEADING);
const keptOpen = cut >= 0 ? previous.slice(0, cut) : previous;
const keptEdit = cut >= 0 ? previous.slice(cut) : '';
const text = (onlyEdit ? keptOpen : openSection + '\n') + (onlyOpen ? keptEdit : editSection);
if (write) writeFileSync(resultsPath, text);
process.stderr.write(write ? 'bench: wrote bench/RESULTS-scale.md\n' : text);
