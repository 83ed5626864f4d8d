#!/usr/bin/env node
// Web editor timings in headless Chromium (software WebGL), written to bench/RESULTS-web.md:
//   - navigation -> first drag-ready frame, and -> the fast gradient path in use (the cage
//     polynomial, the app's default), cold (fresh profile) and warm (reload: the stored session);
//   - while dragging a handle: the drag step (deformCage + reading positions back + updating the
//     geometry) and the time from the pointer event to the rendered frame;
//   - big OBJ files (the spiky ball subdivided, made here with the API's subdivide) dropped on the
//     page: read in the worker, opened, first frame; drag steps measured CPU-side (issue 14).
// Run by hand after `node scripts/setup.mjs --no-native`:
//   node bench/web.mjs [--runs 3] [--models spiky-ball,bunny-remeshed,dragon-remeshed] [--modes dev,preview]
//                      [--big-levels 4,5] (extra levels of the spiky ball: 163,842 and 655,362 vertices; '' for none)
//   --models none --modes none runs the big files alone and replaces only their section of the results.
import { readFileSync, writeFileSync } from 'node:fs';
import { cpus, totalmem, platform, release, loadavg } from 'node:os';
import { join } from 'node:path';
import { startTestServer, launchBrowser, waitReady, waitGradient, visibleHandles, settle, root } from '../tests/browser/harness.mjs';
import { createMrvol } from '../lib/node.mjs';
import { optionReader } from './cli-option.mjs';

const args = process.argv.slice(2);
const option = optionReader(args);
const RUNS = Number(option('--runs', '3'));
// --models none: only the big files; the samples' tables of bench/RESULTS-web.md are kept as they are
const MODELS = option('--models', 'spiky-ball,bunny-remeshed,dragon-remeshed').split(',').filter((m) => m && m !== 'none');
const BIG_LEVELS = option('--big-levels', '4,5').split(',').filter(Boolean).map(Number);
const MODES = option('--modes', 'dev,preview').split(',').filter((m) => m && m !== 'none');
const DRAG_MOVES = 120;

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length ? (s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2) : NaN;
};
const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length ? s[Math.min(s.length - 1, Math.floor(q * s.length))] : NaN;
};
const ms = (x) => (Number.isFinite(x) ? x.toFixed(x < 10 ? 2 : 0) : '–');

async function loadTimes(page) {
  await waitReady(page);
  await waitGradient(page, 180_000);
  const stats = await page.evaluate(() => window.mrvolDebug.stats());
  const source = await page.evaluate(() => window.mrvolDebug.gradientPath());
  // what the theta cache holds for this model (the app caches nothing on the polynomial path)
  const cached = await page.evaluate(() => document.querySelector('[data-testid="cache-list"]')?.textContent ?? '');
  return {
    script: stats.scriptAt, core: stats.coreAt, model: stats.modelAt, ready: stats.readyAt, theta: stats.thetaReadyAt,
    worker: stats.thetaMs, source, cached,
  };
}

async function dragTimes(page, moves = DRAG_MOVES) {
  const handles = await visibleHandles(page);
  const { index } = handles[0];
  const [x, y] = (await page.evaluate(() => window.mrvolDebug.cageScreenPositions()))[index];
  const before = await page.evaluate(() => window.mrvolDebug.stats());
  await page.mouse.move(x, y);
  await page.mouse.down();
  const started = Date.now();
  for (let i = 1; i <= moves; i++) {
    const t = i / moves * 2 * Math.PI;
    await page.mouse.move(x + 50 * Math.sin(t), y - 40 * Math.sin(t / 2));
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => setTimeout(r, 0))));
  }
  const wall = (Date.now() - started) / moves;
  await page.mouse.up();
  await settle(page);
  const after = await page.evaluate(() => window.mrvolDebug.stats());
  const report = await page.evaluate(() => window.mrvolDebug.lastReport());
  const steps = after.steps.slice(before.steps.length);
  const frames = after.frames.slice(before.frames.length);
  const renders = after.renders.slice(before.renders.length);
  return { steps, frames, renders, wall, path: report?.path, error: report?.relativeError };
}

async function measureModel(server, model) {
  const cold = [], warm = [], drags = [];
  for (let run = 0; run < RUNS; run++) {
    const browser = await launchBrowser(server.url); // a fresh profile: nothing cached
    try {
      const page = await browser.newPage();
      await page.goto(`${server.url}?model=${model}`);
      const c = await loadTimes(page);
      cold.push(c);
      await page.waitForTimeout(500); // the session save
      await page.reload();
      const w = await loadTimes(page);
      warm.push(w);
      drags.push(await dragTimes(page));
      process.stderr.write(`${model} run ${run + 1}: cold ready ${ms(c.ready)} fast path ${ms(c.theta)} (${c.source}); warm ready ${ms(w.ready)}\n`);
    } finally {
      await browser.close();
    }
  }
  return { model, cold, warm, drags };
}

const modeName = { dev: 'dev server (serve.mjs)', preview: 'production build (npm start)' };

let version;
const loadAtStart = loadavg()[0];
const results = [];
for (const mode of MODES) {
  const server = await startTestServer({ mode });
  try {
    // Warm the server (dependency bundling, module transforms) with a throw-away profile.
    const warmUp = await launchBrowser(server.url);
    try {
      const page = await warmUp.newPage();
      await page.goto(server.url);
      await waitReady(page);
      version ??= warmUp.context.browser()?.version() ?? (await page.evaluate(() => navigator.userAgent));
    } finally {
      await warmUp.close();
    }
    for (const model of MODELS) results.push({ mode, ...(await measureModel(server, model)) });
  } finally {
    await server.close();
  }
}

/**
 * Thread CPU times from a Chromium trace (category toplevel: each task's wall `dur` and thread
 * `tdur`, which leaves out waiting, e.g. for the GPU process): the page's main thread and its
 * workers, summed, and the page's longest task. Depends little on other jobs on the machine.
 */
async function startThreadTrace(page) {
  const cdp = await page.context().newCDPSession(page);
  const events = [];
  cdp.on('Tracing.dataCollected', ({ value }) => events.push(...value));
  // devtools.timeline: the renderer's tasks (RunTask on its main thread and workers)
  await cdp.send('Tracing.start', { categories: 'devtools.timeline,disabled-by-default-devtools.timeline,toplevel', transferMode: 'ReportEvents' });
  return async () => {
    const ended = new Promise((resolve) => cdp.once('Tracing.tracingComplete', resolve));
    await cdp.send('Tracing.end');
    await ended;
    await cdp.detach();
    const threads = new Map();
    for (const e of events) if (e.ph === 'M' && e.name === 'thread_name') threads.set(`${e.pid}:${e.tid}`, e.args.name);
    // each thread's outermost tasks (RunTask may hold a ThreadControllerImpl::RunTask of the same span)
    const tasks = events.filter((e) => e.ph === 'X' && (e.name === 'RunTask' || e.name === 'ThreadControllerImpl::RunTask'))
      .sort((a, b) => a.ts - b.ts || b.dur - a.dur);
    const ends = new Map();
    const outer = tasks.filter((e) => {
      const key = `${e.pid}:${e.tid}`;
      if (e.ts < (ends.get(key) ?? -Infinity)) return false;
      ends.set(key, e.ts + e.dur);
      return true;
    });
    // the page's renderer: the one whose main thread ran the most
    const busy = new Map();
    for (const e of outer)
      if (threads.get(`${e.pid}:${e.tid}`) === 'CrRendererMain') busy.set(`${e.pid}:${e.tid}`, (busy.get(`${e.pid}:${e.tid}`) ?? 0) + e.dur);
    const pageThread = [...busy].sort((a, b) => b[1] - a[1])[0]?.[0];
    const pagePid = pageThread?.split(':')[0];
    const out = { pageCpu: 0, pageWall: 0, workerCpu: 0, longestCpu: 0, longestWall: 0 };
    for (const e of outer) {
      const key = `${e.pid}:${e.tid}`, cpu = (e.tdur ?? 0) / 1000;
      if (key === pageThread) {
        out.pageCpu += cpu;
        out.pageWall += e.dur / 1000;
        if (cpu > out.longestCpu) Object.assign(out, { longestCpu: cpu, longestWall: e.dur / 1000 });
      } else if (String(e.pid) === pagePid && /Worker/.test(threads.get(key) ?? '')) out.workerCpu += cpu;
    }
    return out;
  };
}

/** A big OBJ dropped on the page (as a user would: a File made in the page): open and drag times. */
async function measureBig(server, levels, mrvol) {
  const spiky = mrvol.readObj(readFileSync(join(root, 'public/models/spiky-ball.obj')));
  const fine = mrvol.subdivide({ positions: spiky.positions, faces: spiky.faces }, { levels });
  const text = Buffer.from(mrvol.writeObj(fine.toMesh()));
  const vertices = fine.vertexCount;
  fine.delete();
  const browser = await launchBrowser(server.url);
  try {
    const page = await browser.newPage();
    await page.goto(server.url);
    await waitReady(page);
    await page.route('**/bench-files/big.obj', (route) => route.fulfill({ body: text, contentType: 'text/plain' }));
    const name = `spiky-${vertices}.obj`;
    const stopTrace = await startThreadTrace(page);
    const t = await page.evaluate(async (name) => {
      const blob = await (await fetch('/bench-files/big.obj')).blob();
      // frame gaps while the worker reads and finds the levels, and from then to the first frame
      // with the model (the page makes the editor on its thread)
      const w = { maxGap: 0, openGap: 0, last: performance.now(), handed: null, running: true };
      window.benchWatch = w;
      const tick = (now) => {
        // the worker's part done: its memory taken over (or, when that failed, the page opening it itself)
        if (/^Opening /.test(document.getElementById('busy-text').textContent) ||
            window.mrvolDebug.openStages().stages.some((s) => s.stage.startsWith('memory taken over'))) w.handed ??= now;
        if (window.mrvolDebug.modelName() === name && window.mrvolDebug.ready()) w.running = false;
        if (!w.running) return;
        if (w.handed === null) w.maxGap = Math.max(w.maxGap, now - w.last);
        else w.openGap = Math.max(w.openGap, now - w.last);
        w.last = now;
        requestAnimationFrame(tick);
      };
      requestAnimationFrame(tick);
      const data = new DataTransfer();
      data.items.add(new File([blob], name));
      const dropped = performance.now();
      document.querySelector('#view canvas').dispatchEvent(new DragEvent('drop', { dataTransfer: data, bubbles: true, cancelable: true }));
      return dropped;
    }, name);
    await page.waitForFunction((n) => window.mrvolDebug.modelName() === n, name, { timeout: 600_000 });
    const opened = await page.evaluate(() => performance.now());
    await waitReady(page, 600_000);
    const ready = await page.evaluate(() => performance.now());
    const cpu = await stopTrace();
    const watch = await page.evaluate(() => window.benchWatch);
    // the first save (the file and positions into IndexedDB, in the store's worker)
    await page.waitForFunction(() => window.mrvolDebug.openStages().stages.some((s) => /written to IndexedDB/.test(s.stage)), null, { timeout: 300_000 }).catch(() => {});
    const stages = (await page.evaluate(() => window.mrvolDebug.openStages())).stages;
    const path = await page.evaluate(() => window.mrvolDebug.gradientPath());
    const drag = await dragTimes(page, 30);
    const fileMb = text.length / 1e6;
    // a level change (0 -> 1): the editor made in a worker and swapped in
    const stopLevelTrace = await startThreadTrace(page);
    const asked = await page.evaluate(() => {
      const w = { maxGap: 0, last: performance.now(), running: true };
      window.levelWatch = w;
      const tick = (now) => {
        if (!w.running) return;
        w.maxGap = Math.max(w.maxGap, now - w.last);
        w.last = now;
        requestAnimationFrame(tick);
      };
      requestAnimationFrame(tick);
      return performance.now();
    });
    await page.locator('[data-testid="level"]').selectOption('1');
    await page.waitForFunction(() => window.mrvolDebug.ready() && window.mrvolDebug.settings().level === 1 && document.querySelector('#busy').hidden, null, { timeout: 600_000 });
    const levelDone = await page.evaluate(() => {
      window.levelWatch.running = false;
      return { at: performance.now(), maxGap: window.levelWatch.maxGap };
    });
    const levelCpu = await stopLevelTrace();
    const levelStages = (await page.evaluate(() => window.mrvolDebug.openStages())).stages;
    const level = { ms: levelDone.at - asked, maxGap: levelDone.maxGap, cpu: levelCpu, stages: levelStages, history: await page.evaluate(() => window.mrvolDebug.historySize()) };
    process.stderr.write(`big ${vertices}: handed over ${ms(watch.handed - t)}, opened ${ms(opened - t)}, first frame ${ms(ready - t)}; step median ${ms(median(drag.steps))}\n`);
    const { levelsFrom, editorFrom } = await page.evaluate(() => window.mrvolDebug.modelFile());
    return { vertices, fileMb, handed: watch.handed - t, readGap: watch.maxGap, openGap: watch.openGap, opened: opened - t, ready: ready - t, path, levelsFrom, editorFrom, drag,
             cpu, stages, level };
  } finally {
    await browser.close();
  }
}

const bigResults = [];
let bigVersion = null;
const bigLoad = [loadavg()[0], null];
if (BIG_LEVELS.length) {
  const mrvol = await createMrvol();
  const server = await startTestServer({ mode: 'preview' });
  try {
    const probe = await launchBrowser(server.url);
    bigVersion = probe.context.browser()?.version() ?? null;
    await probe.close();
    for (const levels of BIG_LEVELS) bigResults.push(await measureBig(server, levels, mrvol));
  } finally {
    await server.close();
  }
  bigLoad[1] = loadavg()[0];
}

const lines = [];
lines.push('# Web editor timings', '');
lines.push(`Measured by \`node bench/web.mjs\` on ${new Date().toISOString().slice(0, 10)}: ${cpus()[0]?.model ?? 'unknown CPU'}, ` +
  `${cpus().length} cores, ${(totalmem() / 2 ** 30).toFixed(0)} GiB, ${platform()} ${release()}, Node ${process.version}, ` +
  `headless Chromium ${version} (WebGL on SwiftShader, software), server on 127.0.0.1, 1200 x 800 viewport, ${RUNS} runs. ` +
  `Other jobs were running on the machine (1-minute load average ${loadAtStart.toFixed(0)} at the start, ${loadavg()[0].toFixed(0)} at the end, ` +
  `on ${cpus().length} cores); medians over the runs.`, '');
lines.push('Times in ms from navigation start (`performance.now()` in the page). "Drag-ready" is the first frame with',
  'the model and its cage drawn. "Fast path in use": the editor on its gradient path (the app\'s default: the',
  'cage polynomial, built from the fine mesh when the editor is made; no θ computed, cached or handed over).',
  'Cold: a fresh browser profile. Warm: a reload (the session restored from IndexedDB). "θ cached": the theta',
  'cache\'s list afterwards. Served by the production bundle (what `npm start` runs:',
  '`node scripts/serve.mjs --preview`, a 2 s vite build then vite preview) or the vite dev server',
  '(`node scripts/serve.mjs`, for working on web/: one request per module).', '');
lines.push('| server | model | run | main.js running | core loaded | model opened | drag-ready frame | fast path in use | path | θ cached |');
lines.push('|---|---|---|---:|---:|---:|---:|---:|---|---|');
for (const r of results)
  for (const [name, runs] of [['cold', r.cold], ['warm', r.warm]]) {
    const m = (f) => ms(median(runs.map(f)));
    const cached = runs[runs.length - 1].cached.trim() || 'nothing';
    lines.push(`| ${modeName[r.mode]} | ${r.model} | ${name} | ${m((c) => c.script)} | ${m((c) => c.core)} | ${m((c) => c.model)} | ` +
      `**${m((c) => c.ready)}** | **${m((c) => c.theta)}** | ${runs[0].source} | ${cached.replace(/\|/g, '/')} |`);
  }
lines.push('', `Dragging one level-0 handle (${DRAG_MOVES} pointer moves per run, each followed by a frame; the path in the last column,`,
  'preservation on, tolerance 1e-6). Step: deformCage + positions back + geometry update. Render: the',
  'renderer.render call (WebGL on SwiftShader, on the CPU). Input to frame: from the pointer event to the end of',
  'the render call of the next animation frame (includes waiting for it: up to one 60 Hz period). Per move: wall',
  'time per move seen from the test driver (includes the round trips of the automation protocol).', '');
lines.push('| server | model | step median | step p95 | render median | render p95 | input to frame median | input to frame p95 | per move (driver) | last relative error |');
lines.push('|---|---|---:|---:|---:|---:|---:|---:|---:|---:|');
for (const r of results) {
  const steps = r.drags.flatMap((d) => d.steps), frames = r.drags.flatMap((d) => d.frames);
  const renders = r.drags.flatMap((d) => d.renders);
  const last = r.drags[r.drags.length - 1];
  lines.push(`| ${modeName[r.mode]} | ${r.model} | ${ms(median(steps))} | ${ms(quantile(steps, 0.95))} | ${ms(median(renders))} | ${ms(quantile(renders, 0.95))} | ${ms(median(frames))} | ` +
    `${ms(quantile(frames, 0.95))} | ${ms(median(r.drags.map((d) => d.wall)))} | ${last.error?.toExponential(1) ?? '–'} (${last.path}) |`);
}
// The big files' section: its own machine line (it may be run alone: --models none).
const bigLines = [];
if (bigResults.length) {
  bigLines.push('## Big files dropped on the page (issues 13, 14)', '',
    `Measured by \`node bench/web.mjs --big-levels ${BIG_LEVELS.join(',')}\` on ${new Date().toISOString().slice(0, 10)}: ${cpus()[0]?.model ?? 'unknown CPU'}, ` +
    `${cpus().length} cores, headless Chromium ${version ?? bigVersion} (WebGL on SwiftShader), production build, a fresh profile, 1200 x 800; ` +
    `1-minute load average ${bigLoad[0].toFixed(0)} at the start of this section and ${bigLoad[1].toFixed(0)} at its end (the machine was shared by other jobs).`, '',
    'The spiky ball subdivided with the API\'s `subdivide` (zero details), written as OBJ in Node, dropped on the page',
    'as a `File` made in the page. Times in ms from the drop: "worker done": the file\'s worker has read and',
    'parsed the file, validated it, found its levels and made the editor (the cage polynomial), and the page has',
    'taken the copy of the worker\'s module memory into a fresh instance ("levels found / editor made in":',
    'worker / worker; page when it fell back to opening the mesh from the hierarchy arrays, or to making the',
    'editor itself); "longest frame gap" while the worker ran (the copy taken over included), then while the page',
    'opened the model (the session, the view\'s buffers, the first upload: on its thread); "opened": the model is',
    'the page\'s; "first frame": drawn, ready to drag. Drag: 30 pointer moves of a level-0 handle; a step measured',
    'CPU-side in the page: the correction, then positionsView() (float32, written in WASM; normalsView() too',
    'under smooth shading, not under the app\'s default flat shading used here)',
    'with only the rewritten vertices copied into the attributes and marked for upload; "steps/s" is 1000 / step median.', '');
  bigLines.push('| vertices | OBJ MB | worker done | levels found / editor made in | longest frame gap in the worker | opened | longest frame gap while the page opens | first frame | path | step median | step p95 | steps/s | input to frame median | last relative error |');
  bigLines.push('|---:|---:|---:|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|');
  for (const b of bigResults) {
    const steps = b.drag.steps, frames = b.drag.frames;
    bigLines.push(`| ${b.vertices.toLocaleString('en-US')} | ${b.fileMb.toFixed(1)} | ${ms(b.handed)} | ${b.levelsFrom} / ${b.editorFrom} | ${ms(b.readGap)} | ${ms(b.opened)} | ${ms(b.openGap)} | ${ms(b.ready)} | ${b.path} | ` +
      `${ms(median(steps))} | ${ms(quantile(steps, 0.95))} | ${(1000 / median(steps)).toFixed(0)} | ${ms(median(frames))} | ${b.drag.error?.toExponential(1) ?? '–'} |`);
  }
  bigLines.push('', 'The page\'s own work, from a Chromium trace of the same runs (thread CPU time of each task, which leaves out',
    'waiting: mostly for the GPU process, whose software WebGL draws a frame of 1.3M triangles in seconds here, the',
    'page\'s thread blocked meanwhile when the frame is handed to the compositor). "Level 0 -> 1": the panel\'s level',
    'changed after the drag, the level-1 editor made in a worker and swapped in (undo history kept).', '');
  bigLines.push('| vertices | what | wall ms (ask to first frame) | longest frame gap | page thread CPU ms | longest page task CPU ms (its wall ms) | workers CPU ms |');
  bigLines.push('|---:|---|---:|---:|---:|---:|---:|');
  for (const b of bigResults) {
    const v = b.vertices.toLocaleString('en-US');
    bigLines.push(`| ${v} | opening (drop to first frame) | ${ms(b.ready)} | ${ms(Math.max(b.readGap, b.openGap))} | ${ms(b.cpu.pageCpu)} | ${ms(b.cpu.longestCpu)} (${ms(b.cpu.longestWall)}) | ${ms(b.cpu.workerCpu)} |`);
    bigLines.push(`| ${v} | level 0 -> 1 (undo steps after: ${b.level.history.undo}) | ${ms(b.level.ms)} | ${ms(b.level.maxGap)} | ${ms(b.level.cpu.pageCpu)} | ${ms(b.level.cpu.longestCpu)} (${ms(b.level.cpu.longestWall)}) | ${ms(b.level.cpu.workerCpu)} |`);
  }
  bigLines.push('', 'What is on the page\'s thread now: taking the worker\'s memory (hundreds of MB) in 16 MB slices with a',
    'frame allowed between them (lib/api.mjs adoptTransferredInSlices), the fresh module instance made while the worker',
    'works, the session and the view\'s buffers (the approximation and detail layers made only when shown), the first',
    'upload. The session\'s first save (the file and the positions into IndexedDB) runs in a worker (web/store-worker.js);',
    'the self-intersection check skips meshes over 200k triangles. A level or scheme change of a model of 100k+',
    'vertices (and its undo) is made in a worker the same way (web/editor-rebuild.js). The longest frame gaps left',
    'are the GPU process\'s: with software compositing each frame\'s commit reads the WebGL canvas back',
    '(GLES2::ReadPixels), and the page\'s thread waits there until SwiftShader has drawn it: seconds for the 655k',
    'model (docs/big-file-frames.md, from `node bench/web-big-trace.mjs`). "opened" and "first frame" are seen at',
    'animation frames (the bench\'s and Playwright\'s rAF polling), so "first frame" is when the page runs again',
    'after that frame: editable. Since the trace the first frame is drawn once (it was three times: a second render',
    'from the ResizeObserver, a third frame for the centre-of-mass marker), without MSAA on SwiftShader, and the',
    'shadow of a mesh over 200k triangles is cast by a coarser level of its hierarchy; the page\'s longest task in',
    'CPU time is the figure its own work is responsible for.');
  bigLines.push('', 'Stages (mrvolDebug.openStages(): wall ms on the thread named; the worker\'s stages on a loaded machine stretch with the load):', '');
  bigLines.push('| vertices | what | stage | thread | ms | MB |');
  bigLines.push('|---:|---|---|---|---:|---:|');
  for (const b of bigResults)
    for (const [what, list] of [['opening', b.stages], ['level 0 -> 1', b.level.stages]])
      for (const st of list)
        bigLines.push(`| ${b.vertices.toLocaleString('en-US')} | ${what} | ${st.stage} | ${st.thread} | ${ms(st.ms)} | ${st.bytes ? (st.bytes / 1e6).toFixed(0) : ''} |`);
  bigLines.push('');
}
lines.push('', 'Where the time goes (from `mrvolDebug.stats()` and CPU profiles taken while writing this):', '',
  '- "main.js running": loading the page\'s modules (dev server: one request per module, three.js included;',
  '  preview: one bundle). "core loaded": compiling and instantiating mrvol-web.wasm, while the OBJ file is',
  '  fetched and IndexedDB opens (cold: compiled without a code cache, slow under this load). "model opened": readObj, openMesh (hierarchy detection), the editor with',
  '  its cage polynomial and the cage; the first frame follows (shaders are compiled while the core loads).',
  '- No θ on any sample: the dragon\'s θ⁰ (341 MB, 10 s, and a 5 s hand-off to the editor) is no longer',
  '  computed; `?gradient=tensor` (or the panel\'s "gradient from") brings the paper\'s path back.');
lines.push('');
const resultsFile = join(root, 'bench/RESULTS-web.md');
let text;
if (results.length) text = [...lines, ...bigLines].join('\n');
else {
  // big files alone: the samples' part of the file as it was, this section in place of the old one
  const old = readFileSync(resultsFile, 'utf8');
  const at = old.indexOf('## Big files dropped on the page');
  const notes = at < 0 ? -1 : old.indexOf('Where the time goes', at); // the samples' notes, after the section or before
  let kept = at < 0 ? old : old.slice(0, at) + (notes < 0 ? '' : old.slice(notes));
  kept = kept.replace(/\n- Big files: [\s\S]*?(?=\n- |\n*$)/, '').trimEnd();
  text = `${kept}\n\n${bigLines.join('\n')}`;
}
writeFileSync(resultsFile, text);
process.stdout.write(text);
