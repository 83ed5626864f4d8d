#!/usr/bin/env node
// Where the time of a big OBJ dropped on the page goes (issue 14: "editable within ~3 s"), every
// process's: a Chromium trace (tests/browser/trace-tasks.mjs, with the GPU process's and the
// compositor's categories) over one drop, cut at the page's own marks (web/open-stages.js: the end
// of each page stage; main.js: the first frame with the model). For each stretch between two marks,
// each thread's top-level busy time (wall and CPU) and, for the busiest, what filled it (trace events'
// self time by name; the page's JS from V8's sampling profiler). Not a benchmark table: a tool to find
// the cause (bench/web.mjs measures; bench/RESULTS-web.md's big-file section says what was found).
//   node bench/web-big-trace.mjs [--level 5] [--top 10] [--keep] [--mode preview|dev]
//   node bench/web-big-trace.mjs --analyze FILE (a trace kept before with --keep)
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { tmpdir } from 'node:os';
import { startTestServer, launchBrowser, waitReady, root } from '../tests/browser/harness.mjs';
import { traceTasks, isTask, CATEGORIES } from '../tests/browser/trace-tasks.mjs';
import { optionReader } from './cli-option.mjs';

const args = process.argv.slice(2);
const option = optionReader(args);
const LEVEL = Number(option('--level', '5'));
const TOP = Number(option('--top', '10'));
const MODE = option('--mode', 'preview');

// the page's tasks, and what the GPU process (SwiftShader's WebGL, the display compositor) and the
// renderer's compositor do meanwhile; V8's samples say which JS fills the page's tasks
const TRACE_CATEGORIES = [...CATEGORIES, 'gpu', 'gpu.service', 'viz', 'cc', 'benchmark', 'blink', 'v8.execute',
  'disabled-by-default-v8.cpu_profiler'];

const f1 = (us) => (us / 1000).toFixed(1);

function names(events) {
  const threads = new Map(), processes = new Map();
  for (const e of events) {
    if (e.ph !== 'M') continue;
    if (e.name === 'thread_name') threads.set(`${e.pid}:${e.tid}`, e.args.name);
    if (e.name === 'process_name') processes.set(e.pid, e.args.name);
  }
  return (pid, tid) => `${processes.get(pid) ?? pid}/${threads.get(`${pid}:${tid}`) ?? tid}`;
}

/** Complete events (X, and B/E pairs made complete) per thread key, sorted by start. */
function completeByThread(events) {
  const out = new Map(), open = new Map();
  const push = (key, e) => (out.get(key) ?? out.set(key, []).get(key)).push(e);
  for (const e of events) {
    const key = `${e.pid}:${e.tid}`;
    if (e.ph === 'X' && Number.isFinite(e.dur)) push(key, e);
    else if (e.ph === 'B') (open.get(key) ?? open.set(key, []).get(key)).push(e);
    else if (e.ph === 'E') {
      const b = open.get(key)?.pop();
      if (b) push(key, { ...b, ph: 'X', dur: e.ts - b.ts, tdur: Number.isFinite(e.tts) && Number.isFinite(b.tts) ? e.tts - b.tts : undefined });
    }
  }
  for (const list of out.values()) list.sort((a, b) => a.ts - b.ts || b.dur - a.dur);
  return out;
}

/** Self time (µs) by event name of the events within [from, to) (clipped). */
function selfTimes(list, from, to) {
  const self = new Map();
  const stack = [];
  const close = (until) => {
    while (stack.length && stack.at(-1).end <= until) {
      const s = stack.pop();
      self.set(s.name, (self.get(s.name) ?? 0) + s.dur - s.children);
    }
  };
  for (const e of list) {
    const start = Math.max(from, e.ts), end = Math.min(to, e.ts + e.dur);
    if (end <= start) continue;
    close(start);
    if (stack.length) stack.at(-1).children += end - start;
    stack.push({ name: e.name, end, dur: end - start, children: 0 });
  }
  close(Infinity);
  return self;
}

/** Top-level tasks' busy time in [from, to): { wall, cpu, longest } in µs (CPU scaled by the clipped share). */
function busy(list, from, to) {
  let wall = 0, cpu = 0, longest = 0, lastEnd = -Infinity;
  for (const e of list) {
    if (!isTask(e) || e.ts < lastEnd) continue; // nested
    lastEnd = e.ts + e.dur;
    const start = Math.max(from, e.ts), end = Math.min(to, e.ts + e.dur);
    if (end <= start) continue;
    const share = (end - start) / e.dur;
    wall += end - start;
    cpu += (Number.isFinite(e.tdur) ? e.tdur : e.dur) * share;
    longest = Math.max(longest, end - start);
  }
  return { wall, cpu, longest };
}

/** The page's sampled JS (V8 ProfileChunk) in [from, to): inclusive time by function. */
function jsInclusive(events, pid, tid, from, to) {
  const profiles = new Map();
  const samples = [];
  for (const e of events) {
    if (e.pid !== pid || (e.name !== 'Profile' && e.name !== 'ProfileChunk')) continue;
    if (e.name === 'Profile') {
      profiles.set(e.id, { tid: e.tid, ts: e.args.data.startTime, nodes: new Map() });
      continue;
    }
    const p = profiles.get(e.id);
    if (!p || p.tid !== tid) continue;
    const { cpuProfile = {}, timeDeltas = [] } = e.args.data;
    for (const n of cpuProfile.nodes ?? []) p.nodes.set(n.id, n);
    const ids = cpuProfile.samples ?? [];
    for (let i = 0; i < ids.length; i++) {
      p.ts += timeDeltas[i] ?? 0;
      samples.push({ ts: p.ts, id: ids[i], nodes: p.nodes });
    }
  }
  samples.sort((a, b) => a.ts - b.ts);
  const inclusive = new Map();
  const frame = (n) => {
    const c = n?.callFrame ?? {};
    const url = (c.url ?? '').replace(/^.*\//, '').replace(/\?.*$/, '');
    return `${c.functionName || '(anonymous)'}${url ? ` ${url}:${(c.lineNumber ?? -1) + 1}` : ''}`;
  };
  for (let i = 0; i < samples.length; i++) {
    const s = samples[i];
    if (s.ts < from || s.ts >= to) continue;
    const dt = Math.min(samples[i + 1]?.ts ?? to, to) - s.ts;
    const seen = new Set();
    for (let n = s.nodes.get(s.id); n; n = s.nodes.get(n.parent)) {
      const key = frame(n);
      if (seen.has(key) || key.startsWith('(root)') || key.startsWith('(program)')) continue;
      seen.add(key);
      inclusive.set(key, (inclusive.get(key) ?? 0) + dt);
    }
  }
  return inclusive;
}

const top = (map, n) => [...map].sort((a, b) => b[1] - a[1]).slice(0, n);

/** The report: the marks, then each stretch between them. */
export function report(events, { topN = TOP } = {}) {
  const name = names(events);
  const byThread = completeByThread(events);
  const marks = events.filter((e) => /^mrvol: /.test(e.name) && (e.ph === 'R' || e.ph === 'I' || e.ph === 'n' || e.ph === 'i'))
    .sort((a, b) => a.ts - b.ts);
  const dropped = marks.find((m) => m.name === 'mrvol: stages begin');
  if (!dropped) throw new Error(`no "mrvol: stages begin" mark in the trace (marks: ${[...new Set(marks.map((m) => m.name))].join(', ')})`);
  const page = { pid: dropped.pid, tid: dropped.tid };
  const after = marks.filter((m) => m.ts >= dropped.ts && m.pid === page.pid);
  const cuts = [dropped, ...after.filter((m) => m !== dropped && m.name !== 'mrvol: rAF')];
  let text = `marks (ms from the drop):\n${cuts.map((m) => `  ${f1(m.ts - dropped.ts).padStart(8)}  ${m.name.slice(7)}`).join('\n')}\n`;
  // the page's animation frames: the gaps over 100 ms (a frame waits for the one before to be drawn)
  const frames = after.filter((m) => m.name === 'mrvol: rAF');
  const gaps = frames.slice(1).map((m, i) => [frames[i].ts, m.ts]).filter(([a, b]) => b - a > 100_000);
  text += `animation frames: ${frames.length}; gaps over 100 ms (from -> to, ms from the drop):\n` +
    `${gaps.map(([a, b]) => `  ${f1(a - dropped.ts).padStart(8)} -> ${f1(b - dropped.ts).padStart(8)} (${f1(b - a)})`).join('\n')}\n`;
  for (const [a, b] of gaps) cuts.push({ ts: a, name: 'mrvol: (a frame gap begins)' }, { ts: b, name: 'mrvol: (the frame gap ends)' });
  cuts.sort((x, y) => x.ts - y.ts);
  for (let i = 0; i + 1 < cuts.length; i++) {
    const from = cuts[i].ts, to = cuts[i + 1].ts;
    if (to - from < 50_000) continue; // stretches under 50 ms: nothing to find
    text += `\n== ${f1(from - dropped.ts)} -> ${f1(to - dropped.ts)} ms (${f1(to - from)} ms): up to "${cuts[i + 1].name.slice(7)}"\n`;
    const rows = [];
    for (const [key, list] of byThread) {
      const [pid, tid] = key.split(':').map(Number);
      const b = busy(list, from, to);
      if (b.wall > 0) rows.push({ key, pid, tid, ...b });
    }
    rows.sort((a, b) => b.wall - a.wall);
    text += '  thread: top-level tasks\' wall / CPU / longest task, ms\n';
    for (const r of rows.slice(0, topN))
      text += `    ${name(r.pid, r.tid).padEnd(44)} ${f1(r.wall).padStart(8)} ${f1(r.cpu).padStart(8)} ${f1(r.longest).padStart(8)}\n`;
    for (const r of rows.slice(0, 4)) {
      text += `  ${name(r.pid, r.tid)}: self time by event name\n`;
      for (const [n, us] of top(selfTimes(byThread.get(r.key), from, to), topN)) text += `    ${f1(us).padStart(8)} ms  ${n}\n`;
    }
    const js = jsInclusive(events, page.pid, page.tid, from, to);
    if (js.size) text += `  the page's JS (sampled), inclusive:\n${top(js, topN).map(([n, us]) => `    ${f1(us).padStart(8)} ms  ${n}`).join('\n')}\n`;
  }
  return text;
}

async function traceDrop() {
  const { createMrvol } = await import('../lib/node.mjs');
  const mrvol = await createMrvol();
  const spiky = mrvol.readObj(readFileSync(join(root, 'public/models/spiky-ball.obj')));
  const fine = mrvol.subdivide({ positions: spiky.positions, faces: spiky.faces }, { levels: LEVEL });
  const text = Buffer.from(mrvol.writeObj(fine.toMesh()));
  const vertices = fine.vertexCount;
  fine.delete();
  const server = await startTestServer({ mode: MODE });
  const browser = await launchBrowser(server.url);
  try {
    const page = await browser.newPage();
    await page.goto(server.url);
    await waitReady(page);
    await page.waitForTimeout(3000); // the environment's idle-time prefiltering done
    await page.route('**/bench-files/big.obj', (route) => route.fulfill({ body: text, contentType: 'text/plain' }));
    const name = `spiky-${vertices}.obj`;
    const trace = await traceTasks(page, { categories: TRACE_CATEGORIES });
    await page.evaluate(async (name) => {
      const blob = await (await fetch('/bench-files/big.obj')).blob();
      // every animation frame marked (a frame waits for the GPU process to finish the one before)
      window.benchFrames = 0;
      const tick = () => {
        performance.mark('mrvol: rAF');
        if (window.mrvolDebug.modelName() === name && window.mrvolDebug.ready()) window.benchFrames++;
        if (window.benchFrames < 3) requestAnimationFrame(tick);
        else performance.mark('mrvol: two frames after the first with the model');
      };
      requestAnimationFrame(tick);
      const data = new DataTransfer();
      data.items.add(new File([blob], name));
      document.querySelector('#view canvas').dispatchEvent(new DragEvent('drop', { dataTransfer: data, bubbles: true, cancelable: true }));
    }, name);
    await page.waitForFunction(() => window.benchFrames >= 3, null, { timeout: 600_000, polling: 100 });
    await page.waitForTimeout(300);
    const { events } = await trace.stop();
    const stages = (await page.evaluate(() => window.mrvolDebug.openStages())).stages;
    process.stdout.write(`${vertices} vertices, ${(text.length / 1e6).toFixed(1)} MB OBJ; stages: ${JSON.stringify(stages.map((s) => [s.stage, s.thread, Math.round(s.ms)]))}\n`);
    if (args.includes('--keep')) {
      const file = join(tmpdir(), `mrvol-big-trace-${vertices}.json`);
      writeFileSync(file, JSON.stringify({ traceEvents: events }));
      process.stdout.write(`trace kept: ${file}\n`);
    }
    return events;
  } finally {
    await browser.close();
    await server.close();
  }
}

if (args.includes('--analyze')) {
  const file = args[args.indexOf('--analyze') + 1];
  process.stdout.write(report(JSON.parse(readFileSync(file, 'utf8')).traceEvents));
} else {
  process.stdout.write(report(await traceDrop()));
}
