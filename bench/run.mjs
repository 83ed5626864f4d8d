#!/usr/bin/env node
// `npm run bench` (after scripts/setup.mjs): benchmarks of the core, natively and as WASM, written
// to bench/RESULTS.md.
//
//   node bench/run.mjs [--only id,id] [--levels 3-8] [--quick] [--rounds 2] [--wait-quiet 0] [--no-write]
//   node bench/run.mjs --list        the benchmark ids and titles
//
//   --rounds R      run the native and WASM core benches R times, alternating, levels >= 7 only
//                   after the first round; each (runner, scheme, level) keeps its least disturbed
//                   round (lowest median). Default 2, 1 with --quick.
//   --wait-quiet S  before each native/WASM/API run, wait until the other processes use less than
//                   a quarter of the CPUs (the machine may be shared), at most S seconds in all.
//                   Default 0.
//
// Three ways to run the same work:
//   native     build/native/mrvol_bench (bench/bench_native.cpp, built by CMake)
//   WASM core  the same bench_native.cpp compiled with emscripten against the very
//              build/wasm/libmrvol_core.a the WASM module is linked with, run by Node: timed
//              inside WASM, no JS API around it
//   JS API     the public API (lib/node.mjs): MultiresMesh.analyze / synthesize, which include
//              the embind copies in and out and the reordering by hierarchy on every call
//
// Adding a benchmark: append { id, title, run } to BENCHMARKS, or export it from a module listed in
// SECTION_MODULES. run(ctx) returns
// { intro?: string, tables: [{ title?, columns: [...], rows: [[...]] }], notes?: [string] } and
// may use ctx.native() / ctx.wasmCore() (the JSON lines of mrvol_bench from the shared rounds, or
// of one run with the given arguments: ctx.native(['--levels', '5']), cached per arguments),
// ctx.api() (the JS API) and ctx.levels. Its Markdown goes between <!-- bench:ID --> and
// <!-- /bench:ID --> in RESULTS.md; sections not run this time are kept as they are.
import { execFileSync, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, readdirSync, statSync, writeFileSync } from 'node:fs';
import { cpus, loadavg, totalmem } from 'node:os';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { performance } from 'node:perf_hooks';
import { emscriptenEnv, root } from '../scripts/setup.mjs';

const { values: opts } = parseArgs({
  options: {
    only: { type: 'string' },
    levels: { type: 'string' },
    quick: { type: 'boolean' },
    rounds: { type: 'string' },
    'wait-quiet': { type: 'string' },
    'no-write': { type: 'boolean' },
    list: { type: 'boolean' },
  },
});

const levelSpec = (opts.levels ?? (opts.quick ? '3-6' : '3-8')).match(/^(\d+)(?:-(\d+))?$/);
if (!levelSpec) throw new Error(`--levels expects L or L1-L2, got '${opts.levels}'`);
const LEVELS = [];
for (let l = Number(levelSpec[1]); l <= Number(levelSpec[2] ?? levelSpec[1]); ++l) LEVELS.push(l);
const SCHEMES = ['loop', 'butterfly', 'linear'];
const MIN_TIME_MS = opts.quick ? 100 : 400;  // per (level, scheme): reps until this much time, at least MIN_REPS
const MIN_REPS = opts.quick ? 3 : 7;
const ROUNDS = Math.max(1, Number(opts.rounds ?? (opts.quick ? 1 : 2)));
const WAIT_QUIET_S = Number(opts['wait-quiet'] ?? 0);
const NOISY_LEVEL = 7;  // extra rounds from this level on (small levels are many fast, stable reps)

const log = (message) => process.stderr.write(`bench: ${message}\n`);

// ---- helpers ----------------------------------------------------------------------------------

function median(values) {
  const v = [...values].sort((a, b) => a - b);
  const n = v.length;
  return n % 2 ? v[(n - 1) / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

function mtime(path) {
  return existsSync(path) ? statSync(path).mtimeMs : 0;
}

const ms = (x) => (x === undefined ? '–' : x < 1 ? x.toFixed(3) : x < 100 ? x.toFixed(2) : x.toFixed(0));
const ratio = (a, b) => (a === undefined || b === undefined ? '–' : (a / b).toFixed(2));
const mvps = (verticesPerSecond) => (verticesPerSecond === undefined ? '–' : (verticesPerSecond / 1e6).toFixed(1));

function parseJsonLines(text, what) {
  const out = [];
  for (const line of text.split('\n')) {
    if (!line.trim()) continue;
    try {
      out.push(JSON.parse(line));
    } catch {
      throw new Error(`${what}: not a JSON line: ${line}`);
    }
  }
  return out;
}

// Fraction of the CPUs busy over `ms` milliseconds (from /proc/stat; this process sleeps meanwhile,
// so it is the others' load), or undefined where there is no /proc/stat.
function cpuBusy(ms = 500) {
  const sample = () => {
    if (!existsSync('/proc/stat')) return undefined;
    const f = readFileSync('/proc/stat', 'utf8').split('\n')[0].trim().split(/\s+/).slice(1).map(Number);
    const idle = f[3] + (f[4] ?? 0);
    return { idle, total: f.reduce((a, b) => a + b, 0) };
  };
  const a = sample();
  if (!a) return undefined;
  Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0, ms);
  const b = sample();
  return b.total > a.total ? 1 - (b.idle - a.idle) / (b.total - a.total) : 0;
}

const busyLog = [];  // { what, busy } before each run

let waitedMs = 0;  // --wait-quiet is a budget for the whole invocation

function waitQuiet(what) {
  let busy = cpuBusy();
  while (busy !== undefined && busy > 0.25 && waitedMs < WAIT_QUIET_S * 1000) {
    const started = performance.now();
    if (waitedMs % 60000 < 5000)
      log(`waiting for a quieter machine (${Math.round(100 * busy)}% of the CPUs busy; waited ${Math.round(waitedMs / 1000)} s ` +
          `of ${WAIT_QUIET_S} s)`);
    Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0, 5000);
    busy = cpuBusy();
    waitedMs += performance.now() - started;
  }
  busyLog.push({ what, busy });
  return busy;
}

// ---- the three runners --------------------------------------------------------------------------

const nativeBench = join(root, 'build/native/mrvol_bench');
const wasmBenchDir = join(root, 'build/bench-wasm');
const wasmBench = join(wasmBenchDir, 'mrvol_bench.js');

// The compile flags CMake gives the core in build/wasm (DEFINES, FLAGS, INCLUDES of
// mrvol_core's objects in build.ninja), so that the bench is compiled like the library it links.
function coreWasmFlags() {
  const fallback = ['-O3', '-DNDEBUG', '-DEIGEN_MPL2_ONLY', '-fwasm-exceptions', '-std=c++17',
                    '-I', join(root, 'wasm/core/include')];
  const ninja = join(root, 'build/wasm/build.ninja');
  if (!existsSync(ninja)) return fallback;
  const m = readFileSync(ninja, 'utf8').match(/^build CMakeFiles\/mrvol_core\.dir\/\S+\.cpp\.o:[^\n]*\n((?: {2}[^\n]*\n)+)/m);
  if (!m) return fallback;
  const vars = Object.fromEntries([...m[1].matchAll(/^ {2}(\w+) = (.*)$/gm)].map((v) => [v[1], v[2]]));
  const flags = [vars.DEFINES, vars.FLAGS, vars.INCLUDES].filter(Boolean).join(' ').split(/\s+/).filter(Boolean);
  return flags.filter((f) => !/^-W/.test(f));
}

// bench_native.cpp with emscripten, with the core's compile flags (coreWasmFlags), linked to
// build/wasm/libmrvol_core.a with the WASM module's memory settings. Rebuilt when the library,
// the bench sources, the core headers or this script are newer.
function buildWasmBench() {
  const lib = join(root, 'build/wasm/libmrvol_core.a');
  if (!existsSync(lib)) throw new Error('build/wasm/libmrvol_core.a is missing: run node scripts/setup.mjs');
  const includeDir = join(root, 'wasm/core/include');
  const sources = readdirSync(join(root, 'bench')).filter((f) => f.endsWith('.cpp')).map((f) => join(root, 'bench', f));
  const headers = readdirSync(join(includeDir, 'mrvol')).map((f) => join(includeDir, 'mrvol', f));
  const newest = Math.max(...[lib, ...sources, ...headers, new URL(import.meta.url).pathname].map(mtime));
  if (existsSync(wasmBench) && mtime(wasmBench) >= newest) return;
  mkdirSync(wasmBenchDir, { recursive: true });
  // The repository's package.json says "type": "module"; emscripten's output here is CommonJS.
  writeFileSync(join(wasmBenchDir, 'package.json'), '{ "type": "commonjs" }\n');
  const flags = coreWasmFlags();
  const args = [...flags, ...sources, lib, '-o', wasmBench,
                '-sENVIRONMENT=node', '-sALLOW_MEMORY_GROWTH=1', '-sMAXIMUM_MEMORY=4GB', '-sINITIAL_MEMORY=64MB',
                '-sTOTAL_STACK=1MB', '-sASSERTIONS=0', '-sEXIT_RUNTIME=1'];
  log(`building build/bench-wasm/mrvol_bench.js (em++ ${flags.join(' ')})`);
  const r = spawnSync('em++', args, { cwd: root, env: emscriptenEnv(), stdio: ['ignore', 'inherit', 'inherit'] });
  if (r.status !== 0) throw new Error(`em++ failed (status ${r.status})`);
  writeFileSync(join(wasmBenchDir, 'flags.txt'), flags.join(' ') + '\n');
}

function runBench(kind, args) {
  const [cmd, argv] = kind === 'native'
    ? [nativeBench, args]
    // --no-experimental-fetch: emscripten 3.1.6 would try to fetch() the .wasm under Node 20.
    // --no-liftoff: V8 compiles the WASM with its optimising compiler from the start. By default
    // it runs baseline code first and tiers up in a background thread, which on a busy machine
    // can come after the warm-up and distort the small levels; the steady state is the same code.
    : [process.execPath, ['--no-experimental-fetch', '--no-liftoff', wasmBench, ...args]];
  if (kind === 'native' && !existsSync(nativeBench)) throw new Error('build/native/mrvol_bench is missing: run node scripts/setup.mjs');
  if (kind === 'wasm') buildWasmBench();
  const busy = waitQuiet(`${kind} ${args.join(' ')}`);
  log(`${kind}: ${kind === 'native' ? 'build/native/mrvol_bench' : 'build/bench-wasm/mrvol_bench.js'} ${args.join(' ')}` +
      (busy === undefined ? '' : ` (other load: ${Math.round(100 * busy)}% of the CPUs)`));
  const started = performance.now();
  const r = spawnSync(cmd, argv, { cwd: root, encoding: 'utf8', maxBuffer: 64 * 1024 * 1024, stdio: ['ignore', 'pipe', 'inherit'] });
  if (r.status !== 0) throw new Error(`${kind} bench failed (status ${r.status}${r.error ? `, ${r.error.message}` : ''})`);
  log(`${kind}: done in ${((performance.now() - started) / 1000).toFixed(1)} s`);
  const rows = parseJsonLines(r.stdout, kind).map((row) => ({ runner: kind, ...row, otherLoad: busy }));
  for (const row of rows) process.stdout.write(JSON.stringify(row) + '\n');
  return rows;
}

// The native and WASM core benches in ROUNDS alternating rounds (native, WASM, then WASM, native
// ...); rounds after the first only for levels >= NOISY_LEVEL and without the one-off costs.
// Transform rows: per (runner, scheme, level) the round with the lowest median, with the medians
// of all rounds in `roundMedians`.
function coreRounds() {
  const all = [];
  const top = LEVELS[LEVELS.length - 1];
  for (let round = 0; round < ROUNDS; ++round) {
    const from = round === 0 ? LEVELS[0] : Math.max(LEVELS[0], NOISY_LEVEL);
    if (from > top) break;
    const args = ['--levels', `${from}-${top}`, '--min-time-ms', String(MIN_TIME_MS), '--min-reps', String(MIN_REPS),
                  ...(round === 0 ? [] : ['--no-setup'])];
    for (const kind of round % 2 === 0 ? ['native', 'wasm'] : ['wasm', 'native'])
      all.push(...runBench(kind, args).map((row) => ({ ...row, round })));
  }
  const best = new Map();
  for (const row of all) {
    if (row.bench !== 'transform') continue;
    const key = `${row.runner} ${row.scheme} ${row.level}`;
    const prev = best.get(key);
    const roundMedians = [...(prev?.roundMedians ?? []), row.medianMs];
    best.set(key, { ...(prev && prev.medianMs <= row.medianMs ? prev : row), roundMedians,
                    minMs: Math.min(row.minMs, prev?.minMs ?? Infinity) });
  }
  return [...all.filter((row) => row.bench !== 'transform'), ...best.values()];
}

function makeContext() {
  const cache = new Map();
  const cached = (key, make) => {
    if (!cache.has(key)) cache.set(key, make());
    return cache.get(key);
  };
  return {
    levels: LEVELS,
    schemes: SCHEMES,
    rounds: ROUNDS,
    // Default: all rounds (coreRounds), shared by every section; other args: one run of that kind.
    native: (args) => (args ? cached(`native ${args.join(' ')}`, () => runBench('native', args))
                            : cached('rounds', coreRounds).filter((r) => r.runner === 'native')),
    wasmCore: (args) => (args ? cached(`wasm ${args.join(' ')}`, () => runBench('wasm', args))
                              : cached('rounds', coreRounds).filter((r) => r.runner === 'wasm')),
    api: () => cached('api', async () => (await import('../lib/node.mjs')).createMrvol()),
  };
}

// ---- the benchmarks -----------------------------------------------------------------------------

function icosahedron() {
  const t = (1 + Math.sqrt(5)) / 2;
  const p = [-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1];
  const s = 1 / Math.hypot(1, t);
  return {
    positions: Float64Array.from(p, (x) => x * s),
    faces: Uint32Array.from([0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
                             3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1]),
  };
}

// The same measurement as mrvol_bench's "transform" lines, through the public JS API.
async function apiTransformRows(ctx) {
  const mrvol = await ctx.api();
  const rows = [];
  const otherLoad = waitQuiet('JS API');
  for (const level of ctx.levels) {
    const mr = mrvol.subdivide(icosahedron(), { levels: level, scheme: 'loop' });
    const x0 = mr.positions();
    for (let i = 0; i < x0.length; i += 3) {
      const l = Math.hypot(x0[i], x0[i + 1], x0[i + 2]);
      x0[i] /= l, x0[i + 1] /= l, x0[i + 2] /= l;
    }
    const n = x0.length / 3;
    // Copy cost alone: positions in (setPositions: embind copy + finiteness check) and out (positions()).
    const copyIn = [], copyOut = [];
    for (let r = 0; r < Math.max(MIN_REPS, 5); ++r) {
      let t = performance.now();
      mr.setPositions(x0);
      copyIn.push(performance.now() - t);
      t = performance.now();
      mr.positions();
      copyOut.push(performance.now() - t);
    }
    for (const scheme of ctx.schemes) {
      // First call: builds and caches the transform for this scheme (subdivide built Loop's).
      let t = performance.now();
      mr.synthesize(mr.analyze(x0, { level: 0, scheme }), { level: 0, scheme });
      const firstMs = performance.now() - t;
      for (let warm = performance.now(), r = 0; r < 3 || performance.now() - warm < 200; ++r)
        mr.synthesize(mr.analyze(x0, { level: 0, scheme }), { level: 0, scheme });
      const total = [], analysis = [], synthesis = [];
      let spent = 0, back;
      while ((total.length < MIN_REPS || spent < MIN_TIME_MS) && total.length < 2000) {
        const a = performance.now();
        const c = mr.analyze(x0, { level: 0, scheme });
        const b = performance.now();
        back = mr.synthesize(c, { level: 0, scheme });
        const e = performance.now();
        analysis.push(b - a), synthesis.push(e - b), total.push(e - a);
        spent += e - a;
      }
      let err = 0;
      for (let i = 0; i < x0.length; ++i) err = Math.max(err, Math.abs(back[i] - x0[i]));
      const med = median(total);
      const row = { runner: 'api', bench: 'transform', scheme, level, vertices: n, reps: total.length, medianMs: med,
                    minMs: Math.min(...total), maxMs: Math.max(...total), analysisMs: median(analysis),
                    synthesisMs: median(synthesis), verticesPerSecond: n / (med / 1000), roundtripError: err,
                    firstCallMs: firstMs, copyInMs: median(copyIn), copyOutMs: median(copyOut), otherLoad };
      process.stdout.write(JSON.stringify(row) + '\n');
      rows.push(row);
    }
    mr.delete();
  }
  return rows;
}

const BENCHMARKS = [
  {
    id: 'wavelet-transform',
    title: 'Wavelet transform: full analysis to level 0 + synthesis back',
    async run(ctx) {
      const native = ctx.native().filter((r) => r.bench === 'transform');
      const wasm = ctx.wasmCore().filter((r) => r.bench === 'transform');
      const api = await apiTransformRows(ctx);
      const find = (rows, scheme, level) => rows.find((r) => r.scheme === scheme && r.level === level);
      const tables = ctx.schemes.map((scheme) => ({
        title: `${scheme}`,
        columns: ['level', 'vertices', 'native ms', 'WASM core ms', 'WASM / native', 'JS API ms', 'JS API / native',
                  'native Mvert/s', 'WASM Mvert/s', 'JS API Mvert/s'],
        rows: ctx.levels.map((level) => {
          const n = find(native, scheme, level), w = find(wasm, scheme, level), a = find(api, scheme, level);
          return [level, n?.vertices ?? a?.vertices, `${ms(n?.medianMs)} (${ms(n?.minMs)})`,
                  `${ms(w?.medianMs)} (${ms(w?.minMs)})`, `${ratio(w?.medianMs, n?.medianMs)} (${ratio(w?.minMs, n?.minMs)})`,
                  `${ms(a?.medianMs)} (${ms(a?.minMs)})`, `${ratio(a?.medianMs, n?.medianMs)} (${ratio(a?.minMs, n?.minMs)})`,
                  mvps(n?.verticesPerSecond), mvps(w?.verticesPerSecond), mvps(a?.verticesPerSecond)];
        }),
      }));
      const top = ctx.levels[ctx.levels.length - 1];
      const goals = ctx.schemes.map((scheme) => {
        const n = find(native, scheme, top), w = find(wasm, scheme, top), a = find(api, scheme, top);
        if (!n || !w) return `- ${scheme}: no result`;
        const r = w.medianMs / n.medianMs, rMin = w.minMs / n.minMs;
        return `- ${scheme}, level ${top} (${n.vertices} vertices): WASM core ${ms(w.medianMs)} ms ` +
               `(${w.medianMs < 50 ? 'under' : 'over'} the 50 ms goal; min ${ms(w.minMs)} ms), ` +
               `WASM / native ${r.toFixed(2)} on medians, ${rMin.toFixed(2)} on minima ` +
               `(goal ≤ 1.5: ${Math.min(r, rMin) <= 1.5 ? (Math.max(r, rMin) <= 1.5 ? 'met' : 'met on one of the two') : 'not met'}); ` +
               `through the JS API ${ms(a?.medianMs)} ms.`;
      });
      const errors = [...native, ...wasm, ...api].map((r) => r.roundtripError);
      const splits = (rows) => rows.filter((r) => r.level === top)
        .map((r) => `${r.scheme} ${ms(r.analysisMs)} + ${ms(r.synthesisMs)}`).join(', ');
      const apiTop = api.filter((r) => r.level === top);
      return {
        intro: [
          'Icospheres: the unit icosahedron subdivided `level` times (Hierarchy::subdivide, zero-detail Loop',
          'synthesis, vertices projected on the unit sphere), 10·4^level + 2 vertices. One measurement is',
          'WaveletTransform::analyze(x, 0) then synthesize(x, 0) on 3N doubles in hierarchy order; the',
          `transform is built before timing. Median over ≥ ${MIN_REPS} repetitions and ≥ ${MIN_TIME_MS} ms, after a warm-up`,
          '(≥ 3 runs and ≥ 200 ms: memory first touched, caches warm; the JS API runs on default V8 flags and',
          'its warm-up also covers the tier-up of the WASM code);',
          'cells read "median (minimum)" in milliseconds, ratios likewise; Mvert/s = vertices / median time.',
          ROUNDS > 1 ? `Levels ≥ ${NOISY_LEVEL} (native and WASM core): ${ROUNDS} rounds, native and WASM alternating, the round with the` +
            '\nlowest median kept (its minimum: the lowest of all rounds); the machine may be shared.' : '',
          '',
          '- **native**: `build/native/mrvol_bench` (g++ -O3, no -march).',
          '- **WASM core**: the same `bench/bench_native.cpp` compiled by emscripten and linked with',
          '  `build/wasm/libmrvol_core.a`, the library inside the WASM module, with the same compile flags; run by',
          '  Node with `--no-liftoff` (optimised code from the start, no tier-up during the warm-up), timed inside',
          '  WASM (std::chrono → performance.now()).',
          '- **JS API**: `MultiresMesh.analyze(x, {level: 0, scheme})` then `.synthesize(...)` from lib/node.mjs.',
          '  **Includes the copies**: each call copies 3N doubles JS → WASM (embind), reorders them to',
          '  hierarchy order and back (2 more copies), then copies the result out to a new Float64Array.',
        ].join('\n'),
        tables,
        notes: [
          '**Goals** (WASM within 1.5× native; ~650k vertices under 50 ms in WASM):',
          ...goals,
          '',
          `Median analysis + synthesis split at level ${top}: native ${splits(native)}; WASM ${splits(wasm)} (ms).`,
          `JS API copy cost at level ${top}: setPositions (copy in) ${ms(apiTop[0]?.copyInMs)} ms, positions() (copy out) ` +
            `${ms(apiTop[0]?.copyOutMs)} ms; first analyze + synthesize of a scheme on a mesh (builds its transform, ` +
            'except for Loop, built by subdivide): ' +
            apiTop.map((r) => `${r.scheme} ${ms(r.firstCallMs)} ms`).join(', ') + '.',
          `Largest round-trip error |synthesize(analyze(x)) − x| over all runs: ${Math.max(...errors).toExponential(1)}.`,
        ],
      };
    },
  },
  {
    id: 'setup-costs',
    title: 'One-off costs: hierarchy, validation, detection, transform construction',
    async run(ctx) {
      const native = ctx.native().filter((r) => r.bench === 'setup');
      const wasm = ctx.wasmCore().filter((r) => r.bench === 'setup');
      const keys = [['subdivideMs', 'Hierarchy::subdivide'], ['validateMs', 'validateMesh'], ['detectMs', 'Hierarchy::detect'],
                    ...ctx.schemes.map((s) => [`${s}TransformMs`, `WaveletTransform (${s})`])];
      return {
        intro: ['On the icospheres above, milliseconds, "native / WASM core": median of up to 5 runs within 300 ms',
                'per item (so one run from level 7 on; the first WASM run of a function includes its compilation).',
                'Hierarchy::detect and validateMesh are what opening an OBJ file costs (`openMesh`, `mrvol info`);',
                'the WaveletTransform constructor runs on the first use of a scheme on a mesh.'].join('\n'),
        tables: [{
          columns: ['level', 'vertices', ...keys.map(([, name]) => name)],
          rows: ctx.levels.map((level) => {
            const n = native.find((r) => r.level === level), w = wasm.find((r) => r.level === level);
            return [level, n?.vertices ?? w?.vertices, ...keys.map(([k]) => `${ms(n?.[k])} / ${ms(w?.[k])}`)];
          }),
        }],
        notes: (() => {
          const top = ctx.levels[ctx.levels.length - 1];
          const n = native.find((r) => r.level === top), w = wasm.find((r) => r.level === top);
          if (!n || !w) return [];
          const perVertex = (x) => `${((1000 * x) / n.vertices).toFixed(2)} µs`;
          return [`Per vertex at level ${top} (native / WASM): ` +
                  keys.map(([k, name]) => `${name} ${perVertex(n[k])} / ${perVertex(w[k])}`).join(', ') + '.'];
        })(),
      };
    },
  },
];

// Further sections from other modules of bench/: every export of the form { id, title, run } is
// appended to BENCHMARKS (or the entries of an exported array `benchmarks`, in its order). A module that is missing is skipped; one that fails to
// load is reported and skipped.
const SECTION_MODULES = ['tensor-solver.mjs'];

async function loadSectionModules() {
  for (const name of SECTION_MODULES) {
    const path = join(root, 'bench', name);
    if (!existsSync(path)) continue;
    try {
      const module = await import(new URL(name, import.meta.url).href);
      // An exported array `benchmarks` gives the order; otherwise the exports' (alphabetical) order.
      for (const value of Array.isArray(module.benchmarks) ? module.benchmarks : Object.values(module))
        if (value && typeof value === 'object' && typeof value.id === 'string' && typeof value.run === 'function' &&
            !BENCHMARKS.some((b) => b.id === value.id))
          BENCHMARKS.push(value);
    } catch (e) {
      log(`warning: bench/${name} not loaded: ${e.message}`);
    }
  }
}

// ---- the report ---------------------------------------------------------------------------------

// The commit of the sources measured, with a + when wasm/ or CMakeLists.txt have uncommitted changes.
function sourceCommit() {
  try {
    const git = (args) => execFileSync('git', ['-C', root, ...args], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] }).trim();
    return git(['rev-parse', '--short', 'HEAD']) + (git(['status', '--porcelain', '--', 'wasm', 'CMakeLists.txt']) ? '+' : '');
  } catch {
    return undefined;
  }
}

function machine() {
  const cpuinfo = existsSync('/proc/cpuinfo') ? readFileSync('/proc/cpuinfo', 'utf8') : '';
  const model = cpuinfo.match(/^model name\s*:\s*(.*)$/m)?.[1] ?? cpus()[0]?.model ?? 'unknown';
  const mhz = cpuinfo.match(/^cpu MHz\s*:\s*(.*)$/m)?.[1];
  const cache = cpuinfo.match(/^cache size\s*:\s*(.*)$/m)?.[1];
  const memKb = Number(readFileSync('/proc/meminfo', 'utf8').match(/^MemTotal:\s*(\d+)/m)?.[1] ?? totalmem() / 1024);
  const tryRun = (cmd, args, env) => {
    try {
      return execFileSync(cmd, args, { encoding: 'utf8', env, stdio: ['ignore', 'pipe', 'ignore'] }).split('\n')[0].trim();
    } catch {
      return 'unknown';
    }
  };
  const os = existsSync('/etc/os-release') ? readFileSync('/etc/os-release', 'utf8').match(/^PRETTY_NAME="?([^"\n]*)/m)?.[1] : undefined;
  const commit = tryRun('git', ['-C', root, 'rev-parse', '--short', 'HEAD']);
  let dirty = '';
  try {
    dirty = execFileSync('git', ['-C', root, 'status', '--porcelain', '--', 'wasm', 'CMakeLists.txt'],
                         { encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] }).trim();
  } catch {}
  const wasmFlags = existsSync(join(wasmBenchDir, 'flags.txt'))
    ? readFileSync(join(wasmBenchDir, 'flags.txt'), 'utf8').trim().replace(/\s*(-I|-isystem)\s*\S+/g, '')
    : 'unknown';
  const nativeNinja = join(root, 'build/native/build.ninja');
  const nativeFlags = existsSync(nativeNinja)
    ? readFileSync(nativeNinja, 'utf8').match(/^build CMakeFiles\/mrvol_core\.dir\/[^\n]*\n(?: {2}[^\n]*\n)*? {2}FLAGS = ([^\n]*)/m)?.[1]
        ?.split(/\s+/).filter((f) => !/^-W/.test(f)).join(' ') ?? 'unknown'
    : 'unknown';
  return {
    source: `commit ${commit}${dirty ? `, with uncommitted changes in: ${[...new Set(dirty.split('\n').map((l) => l.slice(3)))].join(', ')}` : ''}`,
    nativeFlags,
    wasmFlags,
    nproc: tryRun('nproc', []),
    cpu: `${model}${mhz ? `, ${Math.round(Number(mhz))} MHz` : ''}${cache ? `, cache ${cache}` : ''}`,
    memory: `${(memKb / 1024 / 1024).toFixed(1)} GiB`,
    os: `${os ?? 'unknown'}, ${tryRun('uname', ['-r'])}`,
    node: process.version,
    emscripten: tryRun('emcc', ['--version'], emscriptenEnv()).replace(/^emcc \(Emscripten gcc\/clang-like replacement[^)]*\)\s*/, ''),
    compiler: tryRun('g++', ['--version']),
  };
}

function table({ title, columns, rows }) {
  const lines = [];
  if (title) lines.push(`**${title}**`, '');
  lines.push(`| ${columns.join(' | ')} |`, `|${columns.map(() => '---:').join('|')}|`);
  for (const row of rows) lines.push(`| ${row.join(' | ')} |`);
  return lines.join('\n');
}

function sectionMarkdown(bench, result, when, commit) {
  const parts = [`## ${bench.title}`, '', `_Measured ${when}${commit ? ` on commit ${commit}` : ''}._`, ''];
  if (result.intro) parts.push(result.intro, '');
  for (const t of result.tables) parts.push(table(t), '');
  if (result.notes?.length) parts.push(result.notes.join('\n'), '');
  return parts.join('\n');
}

function writeResults(sections, env, load) {
  const path = join(root, 'bench/RESULTS.md');
  const old = existsSync(path) ? readFileSync(path, 'utf8') : '';
  const block = (id, body) => `<!-- bench:${id} -->\n${body.trimEnd()}\n<!-- /bench:${id} -->`;
  const existing = new Map();
  for (const m of old.matchAll(/<!-- bench:([\w-]+) -->\n([\s\S]*?)\n<!-- \/bench:\1 -->/g)) existing.set(m[1], m[2]);
  const header = [
    '# mrvol benchmarks',
    '',
    'Written by `npm run bench` (bench/run.mjs); every section between `<!-- bench:… -->` markers is',
    'rewritten when its benchmark runs (`node bench/run.mjs --only ID`), the others are kept.',
    'Raw measurements: the JSON lines bench/run.mjs prints on stdout.',
    '',
    '## Machine (last run)',
    '',
    `- CPUs (nproc): ${env.nproc}`,
    `- CPU: ${env.cpu}`,
    `- Memory: ${env.memory}`,
    `- OS: ${env.os}`,
    `- Node: ${env.node}`,
    `- emscripten: ${env.emscripten}`,
    `- Native compiler: ${env.compiler}; core flags: \`${env.nativeFlags}\``,
    `- WASM core flags (from build/wasm, used for the bench too): \`${env.wasmFlags}\``,
    `- Sources: ${env.source}`,
    `- Date: ${new Date().toISOString()}`,
    `- Load average (1 min) before / after: ${load.before} / ${load.after}`,
    `- Other processes' CPU use just before each run (% of all CPUs): ${load.busy || 'not sampled in the last run'}`,
    '  (the machine may be shared with other jobs: under load, minima are the better estimate of the cost)',
  ].join('\n');
  const ids = [...new Set([...BENCHMARKS.map((b) => b.id), ...existing.keys()])];
  const body = ids.filter((id) => sections.has(id) || existing.has(id))
    .map((id) => block(id, sections.get(id) ?? existing.get(id))).join('\n\n');
  writeFileSync(path, `${header}\n\n${body}\n`);
  log('wrote bench/RESULTS.md');
}

async function main() {
  await loadSectionModules();
  if (opts.list) {
    for (const b of BENCHMARKS) process.stdout.write(`${b.id}\t${b.title}\n`);
    return;
  }
  const only = opts.only ? new Set(opts.only.split(',')) : null;
  const selected = BENCHMARKS.filter((b) => !only || only.has(b.id));
  if (only) for (const id of only) if (!BENCHMARKS.some((b) => b.id === id)) throw new Error(`unknown benchmark '${id}'`);
  const loadBefore = loadavg()[0].toFixed(2);
  const ctx = makeContext();
  const sections = new Map();
  const started = performance.now();
  const failed = [];
  for (const bench of selected) {
    log(`== ${bench.id}`);
    const when = new Date().toISOString().replace(/\.\d+Z$/, 'Z');
    let result;
    try {
      result = await bench.run(ctx);
    } catch (e) {
      // One failing section does not lose the others; its old text in RESULTS.md is kept.
      log(`error in ${bench.id}: ${e.stack ?? e.message}`);
      failed.push(bench.id);
      continue;
    }
    const md = sectionMarkdown(bench, result, when, sourceCommit());
    sections.set(bench.id, md);
    process.stderr.write(`\n${md}\n`);
  }
  const load = { before: loadBefore, after: loadavg()[0].toFixed(2),
                 busy: busyLog.map(({ what, busy }) => `${what.replace(/ --min-time-ms.*$/, '')} ${busy === undefined ? '?' : Math.round(100 * busy)}%`).join('; ') };
  log(`all done in ${((performance.now() - started) / 1000).toFixed(1)} s`);
  if (!opts['no-write'] && sections.size) writeResults(sections, machine(), load);
  if (failed.length) {
    log(`failed: ${failed.join(', ')}`);
    process.exitCode = 1;
  }
}

main().catch((e) => {
  log(`error: ${e.message}`);
  process.exit(1);
});
