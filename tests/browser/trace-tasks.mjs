// The page's main-thread tasks from a Chromium trace (CDP Tracing on the page's session): each
// top-level task's wall time and the CPU time its thread spent in it, and the page's user-timing
// marks and measures, on the trace's clock. Wall time counts the waits (software WebGL finishing a
// frame in the GPU process, other jobs on a loaded machine); CPU time is the page's own work.
// bench/theta-handoff-trace.mjs is the fuller tool (what fills a task).

export const CATEGORIES = ['toplevel', 'disabled-by-default-devtools.timeline', 'devtools.timeline', 'blink.user_timing'];

/** A top-level task of a thread's message loop (Chromium's trace events). */
export const isTask = (e) => e.ph === 'X' && (e.name === 'RunTask' || e.name === 'ThreadControllerImpl::RunTask') && Number.isFinite(e.dur);

/**
 * Starts tracing; `stop()` resolves to { tasks: [{ ts, ms, cpuMs }], marks: Map(name -> [ts]), measures: [{ name, ts, ms }],
 * events } (ts in µs; events: the raw trace, every process's). `categories`: more than the page's tasks (e.g. the GPU
 * process's 'gpu', 'viz', 'cc': bench/web-big-trace.mjs).
 */
export async function traceTasks(page, { categories = CATEGORIES } = {}) {
  const cdp = await page.context().newCDPSession(page);
  const events = [];
  cdp.on('Tracing.dataCollected', ({ value }) => {
    for (const e of value) events.push(e);
  });
  await cdp.send('Tracing.start', { traceConfig: { includedCategories: categories, recordMode: 'recordAsMuchAsPossible' }, transferMode: 'ReportEvents' });
  return {
    async stop() {
      const ended = new Promise((resolve) => cdp.once('Tracing.tracingComplete', resolve));
      await cdp.send('Tracing.end');
      await ended;
      await cdp.detach().catch(() => {});
      return { ...mainThreadTasks(events), events };
    },
  };
}

function mainThreadTasks(events) {
  const names = new Map();
  for (const e of events) if (e.ph === 'M' && e.name === 'thread_name') names.set(`${e.pid}:${e.tid}`, e.args.name);
  // the page's main thread: the CrRendererMain that has the marks (its own user timing)
  const marked = events.find((e) => /^mrvol: /.test(e.name) && names.get(`${e.pid}:${e.tid}`) === 'CrRendererMain');
  const busy = new Map();
  for (const e of events) {
    const key = `${e.pid}:${e.tid}`;
    if (names.get(key) === 'CrRendererMain' && isTask(e)) busy.set(key, (busy.get(key) ?? 0) + e.dur);
  }
  const key = marked ? `${marked.pid}:${marked.tid}` : [...busy].sort((a, b) => b[1] - a[1])[0]?.[0];
  if (!key) throw new Error('no page main thread in the trace');
  const [pid, tid] = key.split(':').map(Number);
  const tasks = [];
  for (const e of events.filter((x) => x.pid === pid && x.tid === tid && isTask(x)).sort((a, b) => a.ts - b.ts)) {
    if (tasks.length && e.ts < tasks.at(-1).ts + tasks.at(-1).ms * 1000) continue; // nested in the last one
    tasks.push({ ts: e.ts, ms: e.dur / 1000, cpuMs: Number.isFinite(e.tdur) ? e.tdur / 1000 : null });
  }
  const marks = new Map(), open = new Map(), measures = [];
  for (const e of events.filter((x) => x.pid === pid && /^mrvol: /.test(x.name)).sort((a, b) => a.ts - b.ts)) {
    if (e.ph === 'b') open.set(`${e.name}:${e.id ?? e.id2?.local}`, e.ts);
    else if (e.ph === 'e') {
      const k = `${e.name}:${e.id ?? e.id2?.local}`;
      if (open.has(k)) measures.push({ name: e.name, ts: open.get(k), ms: (e.ts - open.get(k)) / 1000 });
      open.delete(k);
    } else marks.set(e.name, [...(marks.get(e.name) ?? []), e.ts]);
  }
  return { tasks, marks, measures };
}

/** The tasks from the last `mark` on: { longest (wall ms), longestCpu (CPU ms), tasks }. */
export function tasksSince({ tasks, marks }, mark) {
  const from = marks.get(mark)?.at(-1);
  if (from === undefined) throw new Error(`no "${mark}" mark in the trace (marks: ${[...marks.keys()].join(', ')})`);
  const after = tasks.filter((t) => t.ts + t.ms * 1000 > from);
  return {
    tasks: after,
    longest: Math.max(0, ...after.map((t) => t.ms)),
    longestCpu: Math.max(0, ...after.map((t) => t.cpuMs ?? t.ms)),
  };
}
