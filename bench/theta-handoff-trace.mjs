#!/usr/bin/env node
// What fills the page's long tasks while a big cached θ is handed to the editor (issue 13: "no long
// hand-off on the main thread"): the dragon sample with ?gradient=tensor is opened (θ⁰ computed in
// the θ worker, stored, read back and handed over in the editor worker), then reloaded (θ⁰ from the
// cache); each phase is recorded as a Chromium trace (CDP Tracing, with V8's sampling profiler).
// For the page's main thread (CrRendererMain) the longest top-level tasks are listed, each with the
// trace events inside it summed by name (self time) and the JS functions sampled in it (self time).
// Not a benchmark table: a tool to find the cause (tests/browser/theta-cache-big.test.mjs bounds it).
//   node bench/theta-handoff-trace.mjs [--tasks 4] [--top 12] [--phase both|computed|cache] [--keep]
//   node bench/theta-handoff-trace.mjs --analyze FILE… (traces kept before)
// --keep writes the raw traces to the temporary folder (mrvol-theta-trace-*.json, for chrome://tracing).
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { tmpdir } from 'node:os';
import { startTestServer, launchBrowser, waitReady, waitTheta } from '../tests/browser/harness.mjs';
import { traceTasks, isTask } from '../tests/browser/trace-tasks.mjs';
import { optionReader } from './cli-option.mjs';

const args = process.argv.slice(2);
const option = optionReader(args);
const TASKS = Number(option('--tasks', '4'));
const TOP = Number(option('--top', '12'));
const PHASE = option('--phase', 'both');
const KEEP = args.includes('--keep');

const CATEGORIES = ['toplevel', 'devtools.timeline', 'disabled-by-default-devtools.timeline', 'v8', 'v8.execute',
  'blink.user_timing', 'disabled-by-default-v8.gc', 'disabled-by-default-v8.cpu_profiler', 'blink', 'gpu', 'cc', 'IndexedDB', 'ipc'];

/** Records a trace over `run()` (tests/browser/trace-tasks.mjs, with CATEGORIES); resolves to its events. */
async function traced(page, run) {
  const trace = await traceTasks(page, { categories: CATEGORIES });
  let recorded;
  try {
    await run();
  } finally {
    recorded = await trace.stop();
  }
  return recorded.events;
}

const ms = (us) => us / 1000;

/** The page's main thread: the CrRendererMain with the most top-level task time. */
function mainThread(events) {
  const names = new Map();
  for (const e of events) if (e.ph === 'M' && e.name === 'thread_name') names.set(`${e.pid}:${e.tid}`, e.args.name);
  const busy = new Map();
  for (const e of events) {
    const key = `${e.pid}:${e.tid}`;
    if (names.get(key) === 'CrRendererMain' && isTask(e)) busy.set(key, (busy.get(key) ?? 0) + e.dur);
  }
  const [key] = [...busy].sort((a, b) => b[1] - a[1])[0] ?? [];
  if (!key) throw new Error('no CrRendererMain thread with tasks in the trace');
  const [pid, tid] = key.split(':').map(Number);
  return { pid, tid };
}


/** Complete events (X, and B/E pairs made complete) of one thread, sorted by start. */
function threadEvents(events, { pid, tid }) {
  const out = [], open = [];
  for (const e of events) {
    if (e.pid !== pid || e.tid !== tid) continue;
    if (e.ph === 'X' && Number.isFinite(e.dur)) out.push(e);
    else if (e.ph === 'B') open.push(e);
    else if (e.ph === 'E') {
      const b = open.pop();
      if (b) out.push({ ...b, ph: 'X', dur: e.ts - b.ts });
    }
  }
  return out.sort((a, b) => a.ts - b.ts || b.dur - a.dur);
}

/** Self time (µs) by event name inside [task.ts, task.ts + task.dur]. */
function selfTimes(list, task) {
  const end = task.ts + task.dur;
  const inside = list.filter((e) => e.ts >= task.ts && e.ts + e.dur <= end);
  const self = new Map();
  const stack = [];
  const close = (until) => {
    while (stack.length && stack.at(-1).end <= until) {
      const s = stack.pop();
      self.set(s.name, (self.get(s.name) ?? 0) + s.dur - s.children);
    }
  };
  for (const e of inside) {
    close(e.ts);
    if (stack.length) stack.at(-1).children += e.dur;
    stack.push({ name: e.name, end: e.ts + e.dur, dur: e.dur, children: 0 });
  }
  close(Infinity);
  return self;
}

/** The sampled JS stacks of a thread: [{ ts, frames: [leaf, …, root] }] from V8's ProfileChunk events. */
function samples(events, { pid, tid }) {
  const profiles = new Map(); // id -> { start, nodes: Map, ts, list }
  const out = [];
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
      out.push({ ts: p.ts, id: ids[i], nodes: p.nodes });
    }
  }
  return out;
}

function frameName(node) {
  const f = node?.callFrame ?? {};
  const url = (f.url ?? '').replace(/^.*\//, '').replace(/\?.*$/, '');
  return `${f.functionName || '(anonymous)'}${url ? ` ${url}:${(f.lineNumber ?? -1) + 1}` : ''}`;
}

/** JS self and inclusive time (µs, by sample count × interval) within a task. */
function jsTimes(sampleList, task) {
  const inside = sampleList.filter((s) => s.ts >= task.ts && s.ts <= task.ts + task.dur);
  const self = new Map(), inclusive = new Map();
  for (let i = 0; i < inside.length; i++) {
    const dt = (inside[i + 1]?.ts ?? task.ts + task.dur) - inside[i].ts;
    const { nodes } = inside[i];
    let node = nodes.get(inside[i].id);
    const leaf = frameName(node);
    self.set(leaf, (self.get(leaf) ?? 0) + dt);
    const seen = new Set();
    for (; node; node = nodes.get(node.parent)) {
      const key = frameName(node);
      if (seen.has(key)) continue;
      seen.add(key);
      inclusive.set(key, (inclusive.get(key) ?? 0) + dt);
    }
  }
  return { self, inclusive, count: inside.length };
}

/** process:thread name -> { pid, tid }. */
function threadsByKey(events) {
  const names = new Map(), processes = new Map(), out = new Map();
  for (const e of events) if (e.ph === 'M' && e.name === 'thread_name') names.set(`${e.pid}:${e.tid}`, e.args.name);
  for (const e of events) if (e.ph === 'M' && e.name === 'process_name') processes.set(e.pid, e.args.name);
  for (const [key, name] of names) {
    const [pid, tid] = key.split(':').map(Number);
    out.set(`${processes.get(pid) ?? pid} ${name}`, { pid, tid });
  }
  return out;
}

/** Busy time (µs) of every other thread's top-level tasks overlapping `task`, keyed by process:thread name. */
function otherThreads(events, main, task) {
  const names = new Map();
  for (const e of events) if (e.ph === 'M' && e.name === 'thread_name') names.set(`${e.pid}:${e.tid}`, e.args.name);
  const processes = new Map();
  for (const e of events) if (e.ph === 'M' && e.name === 'process_name') processes.set(e.pid, e.args.name);
  const busy = new Map();
  const end = task.ts + task.dur;
  for (const e of events) {
    if (!isTask(e) || (e.pid === main.pid && e.tid === main.tid) || e.ts >= end || e.ts + e.dur <= task.ts) continue;
    const key = `${processes.get(e.pid) ?? e.pid} ${names.get(`${e.pid}:${e.tid}`) ?? e.tid}`;
    busy.set(key, (busy.get(key) ?? 0) + Math.min(end, e.ts + e.dur) - Math.max(task.ts, e.ts));
  }
  return busy;
}

const table = (map, top) => [...map].sort((a, b) => b[1] - a[1]).slice(0, top)
  .map(([k, v]) => `    ${ms(v).toFixed(1).padStart(8)} ms  ${k}`).join('\n');

/** The report of one phase's trace: the longest main-thread tasks and what filled them. */
function report(label, events) {
  const thread = mainThread(events);
  const list = threadEvents(events, thread);
  const tasks = list.filter(isTask);
  // top-level only (a RunTask inside another is nested work)
  const top = [];
  for (const t of tasks) if (!top.length || t.ts >= top.at(-1).ts + top.at(-1).dur) top.push(t);
  const start = events.reduce((m, e) => (Number.isFinite(e.ts) && e.ts > 0 && e.ts < m ? e.ts : m), Infinity);
  const sampled = samples(events, thread);
  const longest = [...top].sort((a, b) => b.dur - a.dur).slice(0, TASKS);
  const over = (limit) => top.filter((t) => t.dur > limit * 1000).length;
  let text = `\n== ${label}: main thread ${thread.pid}:${thread.tid}, ${top.length} tasks, ` +
    `${over(50)} over 50 ms, ${over(200)} over 200 ms, ${sampled.length} JS samples\n`;
  for (const t of longest) {
    const cpu = Number.isFinite(t.tdur) ? `, ${ms(t.tdur).toFixed(1)} ms of CPU` : '';
    text += `\n  task at ${ms(t.ts - start).toFixed(0)} ms (from the trace's start), ${ms(t.dur).toFixed(1)} ms${cpu}\n`;
    text += `   trace events, self time by name:\n${table(selfTimes(list, t), TOP)}\n`;
    const others = otherThreads(events, thread, t);
    text += `   other threads meanwhile, top-level busy time (what the task may wait for):\n${table(others, 6)}\n`;
    const [busiest] = [...others].sort((a, b) => b[1] - a[1])[0] ?? [];
    if (busiest) {
      const { pid, tid } = threadsByKey(events).get(busiest);
      const theirs = threadEvents(events, { pid, tid }).filter((e) => e.ts >= t.ts && e.ts + e.dur <= t.ts + t.dur);
      text += `   ${busiest}, self time by name:\n${table(selfTimes(theirs, { ts: t.ts, dur: t.dur }), TOP)}\n`;
    }
    const js = jsTimes(sampled, t);
    if (js.count) text += `   JS samples (${js.count}), self time:\n${table(js.self, TOP)}\n   inclusive:\n${table(js.inclusive, TOP)}\n`;
  }
  return text;
}

// --analyze FILE…: the report of traces kept earlier (--keep), no browser
const kept = args.includes('--analyze') ? args.slice(args.indexOf('--analyze') + 1).filter((a) => a.endsWith('.json')) : null;
if (kept) {
  for (const file of kept) process.stdout.write(report(file, JSON.parse(readFileSync(file, 'utf8')).traceEvents));
  process.exit(0);
}

const server = await startTestServer();
const browser = await launchBrowser(server.url, { viewport: { width: 1280, height: 800 } });
try {
  const page = await browser.newPage();
  const url = `${server.url}?model=dragon-remeshed&gradient=tensor`;
  const phases = [];
  const first = async () => {
    await page.goto(url);
    await waitReady(page, 240_000);
    await waitTheta(page, 900_000);
  };
  if (PHASE === 'cache') await first();
  else phases.push(['computed (θ worker, stored, read back in the editor worker)', await traced(page, first)]);
  const source1 = await page.evaluate(() => window.mrvolDebug.thetaSource());
  // the entry written (listed) before the reload
  await page.waitForFunction(() => /dragon-remeshed loop e=0 +[\d.]+ MB/.test(document.querySelector('[data-testid="cache-list"]').textContent), null, { timeout: 300_000 });
  if (PHASE !== 'computed') {
    phases.push(['from the cache after a reload', await traced(page, async () => {
      await page.goto(url);
      await waitReady(page, 240_000);
      await waitTheta(page, 600_000);
    })]);
  }
  const stages = await page.evaluate(() => window.mrvolDebug.openStages());
  let out = `θ sources: first ${source1}, last ${await page.evaluate(() => window.mrvolDebug.thetaSource())}\n` +
    `last hand-off's stages: ${JSON.stringify(stages.stages.map((s) => [s.stage, s.thread, Math.round(s.ms)]))}\n`;
  for (const [i, [label, events]] of phases.entries()) {
    if (KEEP) writeFileSync(join(tmpdir(), `mrvol-theta-trace-${i}.json`), JSON.stringify({ traceEvents: events }));
    out += report(label, events);
  }
  process.stdout.write(out);
} finally {
  await browser.close();
  await server.close();
}
