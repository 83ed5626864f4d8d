#!/usr/bin/env node
// Where the page's thread spends its time while a big OBJ dropped on it opens: a Chromium CPU
// profile of the page (through playwright's CDP session) from the drop to the first frame with the
// model, summed by function (self and inclusive time), plus the app's own per-stage times
// (mrvolDebug.openStages(): each stage's time and the thread it ran on). Not a benchmark table:
// a tool for finding what to move off the page's thread (bench/web.mjs measures).
//   node bench/web-open-profile.mjs [--levels 5] [--mode dev|preview] [--top 40]
import { existsSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { tmpdir } from 'node:os';
import { startTestServer, launchBrowser, waitReady, root } from '../tests/browser/harness.mjs';
import { createMrvol } from '../lib/node.mjs';
import { optionReader } from './cli-option.mjs';

const args = process.argv.slice(2);
const option = optionReader(args);
const LEVELS = Number(option('--levels', '5'));
const MODE = option('--mode', 'dev');
const TOP = Number(option('--top', '40'));

/** The spiky ball subdivided LEVELS times as OBJ (kept in the temporary folder between runs). */
async function bigObj() {
  const file = join(tmpdir(), `mrvol-spiky-${LEVELS}.obj`);
  if (existsSync(file)) return readFileSync(file);
  const mrvol = await createMrvol();
  const spiky = mrvol.readObj(readFileSync(join(root, 'public/models/spiky-ball.obj')));
  const fine = mrvol.subdivide({ positions: spiky.positions, faces: spiky.faces }, { levels: LEVELS });
  const text = Buffer.from(mrvol.writeObj(fine.toMesh()));
  fine.delete();
  writeFileSync(file, text);
  return text;
}

/** Self and inclusive time (ms) per function of a CPU profile, the `top` biggest of each. */
function summarize(profile, top) {
  const nodes = new Map(profile.nodes.map((n) => [n.id, n]));
  const parent = new Map();
  for (const n of profile.nodes) for (const c of n.children ?? []) parent.set(c, n.id);
  const name = (n) => {
    const f = n.callFrame;
    return `${f.functionName || '(anonymous)'} ${f.url.replace(/^.*\//, '').replace(/\?.*$/, '')}:${f.lineNumber + 1}`;
  };
  const self = new Map(), inclusive = new Map();
  const { samples, timeDeltas } = profile;
  for (let i = 0; i < samples.length; i++) {
    const dt = (timeDeltas[i + 1] ?? 0) / 1000;
    const n = nodes.get(samples[i]);
    self.set(name(n), (self.get(name(n)) ?? 0) + dt);
    const seen = new Set();
    for (let id = samples[i]; id !== undefined; id = parent.get(id)) {
      const key = name(nodes.get(id));
      if (seen.has(key)) continue;
      seen.add(key);
      inclusive.set(key, (inclusive.get(key) ?? 0) + dt);
    }
  }
  const list = (m) => [...m].sort((a, b) => b[1] - a[1]).slice(0, top).map(([k, v]) => `${v.toFixed(0).padStart(7)} ms  ${k}`).join('\n');
  return `self time:\n${list(self)}\n\ninclusive time:\n${list(inclusive)}`;
}

const text = await bigObj();
const server = await startTestServer({ mode: MODE });
const browser = await launchBrowser(server.url);
try {
  const page = await browser.newPage();
  await page.goto(server.url);
  await waitReady(page);
  await page.route('**/bench-files/big.obj', (route) => route.fulfill({ body: text, contentType: 'text/plain' }));
  const name = `spiky-${LEVELS}.obj`;
  await page.evaluate(async () => {
    window.profileBlob = await (await fetch('/bench-files/big.obj')).blob();
  });
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Profiler.enable');
  await cdp.send('Profiler.setSamplingInterval', { interval: 500 });
  await cdp.send('Profiler.start');
  const TRACE = args.includes('--trace');
  const traceEvents = [];
  if (TRACE) {
    cdp.on('Tracing.dataCollected', ({ value }) => traceEvents.push(...value));
    await cdp.send('Tracing.start', { categories: 'devtools.timeline,toplevel,blink,gpu,v8,disabled-by-default-devtools.timeline', transferMode: 'ReportEvents' });
  }
  const dropped = await page.evaluate((name) => {
    const w = { maxGap: 0, last: performance.now(), gaps: [] };
    window.profileWatch = w;
    const tick = (now) => {
      const gap = now - w.last;
      if (gap > 100) w.gaps.push([Math.round(w.last), Math.round(gap)]);
      w.maxGap = Math.max(w.maxGap, gap);
      w.last = now;
      if (!(window.mrvolDebug.modelName() === name && window.mrvolDebug.ready())) requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
    const data = new DataTransfer();
    data.items.add(new File([window.profileBlob], name));
    document.querySelector('#view canvas').dispatchEvent(new DragEvent('drop', { dataTransfer: data, bubbles: true, cancelable: true }));
    return performance.now();
  }, name);
  await page.waitForFunction((n) => window.mrvolDebug.modelName() === n && window.mrvolDebug.ready(), name, { timeout: 600_000, polling: 200 });
  const done = await page.evaluate(() => performance.now());
  const { profile } = await cdp.send('Profiler.stop');
  if (TRACE) {
    const ended = new Promise((resolve) => cdp.once('Tracing.tracingComplete', resolve));
    await cdp.send('Tracing.end');
    await ended;
    writeFileSync(join(tmpdir(), 'mrvol-open-trace.json'), JSON.stringify(traceEvents));
  }
  const watch = await page.evaluate(() => window.profileWatch);
  const stages = await page.evaluate(() => window.mrvolDebug.openStages?.() ?? null);
  writeFileSync(join(tmpdir(), 'mrvol-open.cpuprofile'), JSON.stringify(profile));
  process.stdout.write(`drop to first frame ${(done - dropped).toFixed(0)} ms; longest frame gap ${watch.maxGap.toFixed(0)} ms\n` +
    `gaps over 100 ms (at, ms from navigation): ${JSON.stringify(watch.gaps.map(([at, g]) => [at - Math.round(dropped), g]))}\n` +
    `stages: ${JSON.stringify(stages, null, 1)}\n\n${summarize(profile, TOP)}\n`);
} finally {
  await browser.close();
  await server.close();
}
