#!/usr/bin/env node
// Web editor timings in headless Chromium (software WebGL), written to bench/RESULTS-web.md:
//   - navigation -> first drag-ready frame, and -> theta in use, cold (fresh profile: theta computed
//     in the worker) and warm (reload: theta from IndexedDB);
//   - while dragging a handle: the drag step (deformCage + reading positions back + updating the
//     geometry) and the time from the pointer event to the rendered frame.
// Run by hand after `node scripts/setup.mjs --no-native`:
//   node bench/web.mjs [--runs 3] [--models spiky-ball,bunny-remeshed] [--modes dev,preview]
import { writeFileSync } from 'node:fs';
import { cpus, totalmem, platform, release } from 'node:os';
import { join } from 'node:path';
import { startTestServer, launchBrowser, waitReady, waitTheta, visibleHandles, settle, root } from '../tests/browser/harness.mjs';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 && args[i + 1] ? args[i + 1] : fallback;
};
const RUNS = Number(option('--runs', '3'));
const MODELS = option('--models', 'spiky-ball,bunny-remeshed').split(',');
const MODES = option('--modes', 'dev,preview').split(',');
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
  await waitTheta(page, 180_000);
  const stats = await page.evaluate(() => window.mrvolDebug.stats());
  const source = await page.evaluate(() => window.mrvolDebug.thetaSource());
  return {
    script: stats.scriptAt, core: stats.coreAt, model: stats.modelAt, ready: stats.readyAt, theta: stats.thetaReadyAt,
    worker: stats.thetaMs, source,
  };
}

async function dragTimes(page) {
  const handles = await visibleHandles(page);
  const { index } = handles[0];
  const [x, y] = (await page.evaluate(() => window.mrvolDebug.cageScreenPositions()))[index];
  const before = await page.evaluate(() => window.mrvolDebug.stats());
  await page.mouse.move(x, y);
  await page.mouse.down();
  const started = Date.now();
  for (let i = 1; i <= DRAG_MOVES; i++) {
    const t = i / DRAG_MOVES * 2 * Math.PI;
    await page.mouse.move(x + 50 * Math.sin(t), y - 40 * Math.sin(t / 2));
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => setTimeout(r, 0))));
  }
  const wall = (Date.now() - started) / DRAG_MOVES;
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
      if (c.source !== 'computed') throw new Error(`cold run took theta from ${c.source}`);
      cold.push(c);
      await page.waitForTimeout(500); // the cache write and the session save
      await page.reload();
      const w = await loadTimes(page);
      if (w.source !== 'cache') throw new Error(`warm run took theta from ${w.source}`);
      warm.push(w);
      drags.push(await dragTimes(page));
      process.stderr.write(`${model} run ${run + 1}: cold ready ${ms(c.ready)} theta ${ms(c.theta)}; warm ready ${ms(w.ready)} theta ${ms(w.theta)}\n`);
    } finally {
      await browser.close();
    }
  }
  return { model, cold, warm, drags };
}

const modeName = { dev: 'dev server (serve.mjs)', preview: 'production build (npm start)' };

let version;
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

const lines = [];
lines.push('# Web editor timings', '');
lines.push(`Measured by \`node bench/web.mjs\` on ${new Date().toISOString().slice(0, 10)}: ${cpus()[0]?.model ?? 'unknown CPU'}, ` +
  `${cpus().length} cores, ${(totalmem() / 2 ** 30).toFixed(0)} GiB, ${platform()} ${release()}, Node ${process.version}, ` +
  `headless Chromium ${version} (WebGL on SwiftShader, software), server on 127.0.0.1, 1200 x 800 viewport, ${RUNS} runs. ` +
  'Other jobs were running on the machine; medians over the runs.', '');
lines.push('Times in ms from navigation start (`performance.now()` in the page). "Drag-ready" is the first frame with',
  'the model and its cage drawn: dragging works from then on, on the matrix-free path until theta arrives.',
  'Cold: a fresh browser profile, theta computed in the worker. Warm: a reload, theta read from IndexedDB',
  '(and the session restored from localStorage). Served by the production bundle (what `npm start` runs:',
  '`node scripts/serve.mjs --preview`, a 2 s vite build then vite preview) or the vite dev server',
  '(`node scripts/serve.mjs`, for working on web/: one request per module).', '');
lines.push('| server | model | run | main.js running | core loaded | model opened | drag-ready frame | theta in use | worker computeTheta |');
lines.push('|---|---|---|---:|---:|---:|---:|---:|---:|');
for (const r of results)
  for (const [name, runs] of [['cold', r.cold], ['warm', r.warm]]) {
    const m = (f) => ms(median(runs.map(f)));
    lines.push(`| ${modeName[r.mode]} | ${r.model} | ${name} | ${m((c) => c.script)} | ${m((c) => c.core)} | ${m((c) => c.model)} | ` +
      `**${m((c) => c.ready)}** | **${m((c) => c.theta)}** | ${name === 'cold' ? m((c) => c.worker) : '–'} |`);
  }
lines.push('', `Dragging one level-0 handle (${DRAG_MOVES} pointer moves per run, each followed by a frame; tensor path,`,
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
lines.push('', 'Where the time goes (from `mrvolDebug.stats()` and CPU profiles taken while writing this):', '',
  '- "main.js running": loading the page\'s modules (dev server: one request per module, three.js included;',
  '  preview: one bundle). "core loaded": compiling and instantiating mrvol-web.wasm, while the OBJ file is',
  '  fetched and IndexedDB opens. "model opened": readObj, openMesh (hierarchy detection), the editor and the',
  '  cage; the first frame follows (shaders are compiled while the core loads).',
  '- Cold theta: the worker has its core ready by then (it gets the page\'s compiled module) and starts beside',
  '  the cache lookup; the rest is openMesh in the worker, computeTheta, moving the file to the page',
  '  (transferred), readTheta and useTheta. Right after start-up the main thread spends a few hundred ms in',
  '  native code ("(program)" in the profile; most likely the first WebGL frames on SwiftShader), which delays the answers.',
  '- Warm theta: reading the cached file from IndexedDB (its size is in the theta readout: 9 MB for the spiky ball) takes most',
  '  of the gap; the read is started from the session\'s fingerprint before the core has loaded.',
  '- A drag step costs well under a millisecond with the tensor; the frame rate is bound by the display',
  '  (input to frame is about one 60 Hz period).');
lines.push('');
writeFileSync(join(root, 'bench/RESULTS-web.md'), lines.join('\n'));
process.stdout.write(lines.join('\n'));
