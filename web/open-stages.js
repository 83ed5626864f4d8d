// Where the time of opening a big model (or rebuilding its editor) goes, stage by stage, and on
// which thread each stage ran ('worker': the file's or the editor's worker, off the page's thread;
// 'page': the page's thread; 'gpu': waiting for the first frame to be drawn). mrvolDebug.openStages()
// gives the last opening's list; bench/web.mjs and the browser tests read it. CPU times measured
// where the work runs, so they say little about other jobs on the machine.
let stages = [];
let started = null;

/** Starts a new list (an opening or a rebuild begins). */
export function beginStages(what) {
  stages = [];
  started = performance.now();
  stages.what = what;
  performance.mark('mrvol: stages begin'); // where a trace's window of this rebuild starts (theta-cache-big)
}

/** Adds a stage: { stage, thread, ms } (and any details, e.g. bytes). */
export function addStage(stage, thread, ms, details = {}) {
  stages.push({ stage, thread, ms: Math.round(ms * 10) / 10, ...details });
  if (thread === 'page') performance.mark(`mrvol: ${stage}`); // where it ended, in a trace (bench/web-big-trace.mjs)
}

/** Runs fn on the page's thread as one stage; returns its result. */
export function pageStage(stage, fn) {
  const t = performance.now();
  try {
    return fn();
  } finally {
    addStage(stage, 'page', performance.now() - t);
  }
}

/** The stages so far: { what, since (ms from the beginning), stages: [...] }. */
export function openStages() {
  return { what: stages.what ?? null, since: started === null ? null : Math.round(performance.now() - started), stages: stages.map((s) => ({ ...s })) };
}

/**
 * A worker's own list of stages, sent to the page with its result: timed(stage, fn) runs fn as one
 * stage, add(stage, ms, details) records one measured otherwise.
 */
export function workerStages() {
  const list = [];
  const add = (stage, ms, details = {}) => { list.push({ stage, thread: 'worker', ms: Math.round(ms * 10) / 10, ...details }); };
  function timed(stage, fn) {
    const t = performance.now();
    try {
      return fn();
    } finally {
      add(stage, performance.now() - t);
    }
  }
  return { list, add, timed };
}
