// Opening a mesh file of any format the core reads (OBJ, STL, PLY, OFF, glTF/GLB): small files are
// parsed here at once, bigger ones in a module worker (open-worker.js) with a progress bar and a
// cancel button in the status strip, so the page keeps drawing while a big file is read.
import { MAX_FILE_BYTES, sizeMessage } from './file-limits.js';
import { loadMrvol } from './mrvol.js';
import { warmUpInSteps } from './module-transfer.js';
import { addStage, beginStages } from './open-stages.js';
import { memorySlicesFrom } from './memory-slices.js';

const $ = (id) => document.getElementById(id);
// Under this size the parse takes well under a frame's worth of waiting; no worker needed.
const WORKER_BYTES = 1_000_000;

let running = null; // { worker, reject, ahead? (readMeshFile: the instance grown ahead, growAhead) }

// One file worker started ahead, once the page is idle: its script loaded and its core warmed up
// (open-worker.js), a dropped file goes to it at once, where a worker started then took a second or
// more before it read anything (bench/NOTES-transfer.md). With it the page's fresh instance for the
// worker's editor (freshInstance), whose making was a long task at the drop. Each is used once; the
// next ones start when the page is idle again. They cost an idle worker and an instance of the
// module, each with a small heap.
let spare = null; // { worker, failed }
let spareInstance = null; // a promise of freshInstance()
let sparesAsked = false;
/**
 * Starts the spare file worker now, when there is none (the page's start, once its first model is
 * open: a file dropped as soon as the page is ready would find a worker started when idle still
 * loading its script and core).
 */
export function startFileWorker() {
  if (spare || running) return;
  const worker = new Worker(new URL('./open-worker.js', import.meta.url), { type: 'module', name: 'mrvol-open' });
  const made = { worker, failed: false };
  worker.onerror = (e) => {
    e.preventDefault?.();
    made.failed = true;
  };
  spare = made;
}
/** Starts the spare file worker and instance that are missing when the page is next idle (again after each job). */
export function keepFileWorkerReady() {
  if (sparesAsked || (spare && spareInstance)) return;
  sparesAsked = true;
  const start = () => {
    sparesAsked = false;
    if (running) return; // a job's end asks again
    startFileWorker();
    spareInstance ??= freshInstance({ stage: false });
  };
  (window.requestIdleCallback ?? ((f) => setTimeout(f, 200)))(start, { timeout: 5000 });
}
/** A fresh instance for a worker's editor: the spare one when there is one (made ahead), else made now. */
export function takeFreshInstance() {
  const instance = spareInstance ?? freshInstance();
  spareInstance = null;
  return instance;
}
function takeFileWorker() {
  const ready = spare && !spare.failed ? spare.worker : null;
  if (spare && !ready) spare.worker.terminate();
  spare = null;
  return ready ?? new Worker(new URL('./open-worker.js', import.meta.url), { type: 'module', name: 'mrvol-open' });
}

let holdView = () => {};
/** What shows and hides of the busy strip tells `hold(shown)` (main.js: the view keeps its size meanwhile, Viewer.holdSize). */
export function onFileProgressShown(hold) {
  holdView = hold;
}

/** The progress in the status strip: fraction 0..1 (null: indeterminate) and a label; text null hides it. */
export function showFileProgress(text, fraction = null) {
  const box = $('busy');
  const change = box.hidden !== (text === null);
  box.hidden = text === null;
  if (change) holdView(text !== null); // after the layout changed: released, the view is measured as it is
  $('busy-text').textContent = text ?? '';
  $('busy-text').title = text ?? ''; // the whole text where a phone cuts it
  const bar = $('busy-bar');
  if (fraction === null) bar.removeAttribute('value');
  else bar.value = fraction;
}

/** Stops the running read (the cancel button); the promise of readMeshFile rejects with { cancelled }. */
export function cancelFileRead() {
  if (!running) return false;
  const { worker, reject } = running;
  running.ahead?.stop();
  running = null;
  worker.terminate();
  showFileProgress(null);
  keepFileWorkerReady(); // for the next file
  reject(Object.assign(new Error('cancelled'), { cancelled: true }));
  return true;
}

/**
 * Another job shown in the status strip with the same cancel button (editor-rebuild.js): the
 * running file read is cancelled first. Returns the job; cancelled(job) tells whether it was since.
 */
export function startBusyJob(worker, reject) {
  cancelFileRead();
  running = { worker, reject };
  return running;
}
export const cancelled = (job) => running !== job;
/** Ends a job started with startBusyJob (its worker stopped, the strip hidden). */
export function endBusyJob(job) {
  if (running === job) running = null;
  job.worker.terminate();
  showFileProgress(null);
  keepFileWorkerReady(); // the spare instance, when the job took it
}

/**
 * The worker's mesh and editor in a fresh instance of the module (module-transfer.js): the
 * MultiresMesh, whose first createEditor at the worker's level and scheme is the editor made
 * there; null when that fails (the page then opens the mesh from the hierarchy arrays). The
 * memory (a GB or more for a big mesh) comes from the worker in slices (`memory`: memory-slices.js
 * memorySlicesFrom, which the caller feeds with the worker's messages), the page drawing between
 * them; `progress(fraction)` after each, `cancelled()` checked too (then it rejects with { cancelled }).
 */
export async function adopt(transfer, { memory, progress = () => {}, cancelled = () => false, instance = takeFreshInstance() }) {
  try {
    const fresh = await pageStageAsync('core instance for the editor (waited for)', () => instance);
    const t = performance.now();
    const between = (fraction) => {
      if (cancelled()) throw Object.assign(new Error('cancelled'), { cancelled: true });
      progress(fraction);
      return new Promise((resolve) => setTimeout(resolve, 0));
    };
    const mr = await fresh.adoptTransferredInSlices({ ...transfer, memory: memory.slices }, { between });
    const bytes = { bytes: transfer.memoryBytes };
    addStage('memory copied for the page', 'worker', memory.workerMs, bytes); // slice by slice, while the page took them
    addStage('memory taken over (in slices)', 'page', performance.now() - t, bytes);
    return mr;
  } catch (e) {
    if (e.cancelled) throw e;
    console.warn(`the worker's editor could not be taken over (${e.message}): opening the mesh here`);
    return null;
  }
}

/**
 * A fresh instance of the module, warmed up (module-transfer.js), for adopt: started when a worker
 * starts, it is made while the worker works (its instantiation and warm-up are the page's, a few
 * hundred ms, not waited for at the end). Its own stage says how long it took.
 */
export function freshInstance({ stage = true } = {}) {
  const started = performance.now();
  const making = (async () => {
    const instance = await loadMrvol();
    await warmUpInSteps(instance, () => new Promise((resolve) => setTimeout(resolve, 0))); // frames between its calls
    if (stage) addStage('core instance for the editor made (wall time, while the worker works)', 'page', performance.now() - started);
    return instance;
  })();
  making.catch(() => {}); // adopt awaits it and says why
  return making;
}

// Memory the worker's editor takes per vertex (the memory in use it hands over at level 0, the
// cage polynomial, the biggest: 437 MB at 655k vertices, 111 MB at 164k); the page's instance is
// grown to a little less, so it never holds much more than it will use.
const TRANSFER_BYTES_PER_VERTEX = 600;

/**
 * The instance that will take the worker's editor, grown ahead to about the memory it will take
 * and its pages written once (lib/api.mjs growMemoryAhead) while the worker still works: the
 * take-over's copy then writes pages that exist instead of faulting on each (most of its time).
 * In 16 MB slices with a task between them (the page keeps drawing); stop() ends it early.
 */
function growAhead(instance, vertices) {
  const stopping = new AbortController();
  const started = performance.now();
  const done = instance
    .then((fresh) => fresh.growMemoryAhead(vertices * TRANSFER_BYTES_PER_VERTEX, { signal: stopping.signal }))
    .then((bytes) => addStage('memory grown ahead for the editor (while the worker works)', 'page', performance.now() - started, { bytes }))
    .catch(() => {}); // only a head start: the take-over grows what is missing
  return { stop: () => stopping.abort(), done };
}

async function pageStageAsync(stage, fn) {
  const t = performance.now();
  try {
    return await fn();
  } finally {
    addStage(stage, 'page', performance.now() - t);
  }
}

/**
 * Reads a mesh file: { file } (a File) or { bytes } (Uint8Array, e.g. a stored session's), with its
 * name. Resolves to { mesh, bytes: Uint8Array, format, hierarchy?, openError? } (a worker's: the
 * hierarchy it found, or why the mesh does not open: { message, offer }; with `editor`
 * ({ level, scheme }) `opened`: the MultiresMesh made there with that editor, see adopt); rejects with a message naming what is
 * wrong (`size`: true when the file is too big, `cancelled` when cancelled).
 */
export async function readMeshFile(mrvol, { file = null, bytes = null, name, editor = null }) {
  const size = file ? file.size : bytes.byteLength;
  if (size > MAX_FILE_BYTES) throw Object.assign(new Error(sizeMessage({ bytes: size })), { size: true });
  if (size <= WORKER_BYTES) {
    const data = bytes ?? new Uint8Array(await file.arrayBuffer());
    return { mesh: mrvol.readMesh(data, { name }), bytes: data, format: mrvol.detectFormat(data, name) };
  }
  cancelFileRead();
  beginStages(`opening ${name}`);
  const instance = editor ? takeFreshInstance() : null; // made ahead, or while the worker works
  const worker = takeFileWorker();
  const asked = performance.now();
  let started = false; // the worker's first message: it has the file
  const mb = `${(size / 1e6).toFixed(1)} MB`;
  showFileProgress(`Reading ${name} (${mb})…`, 0);
  return new Promise((resolve, reject) => {
    const job = { worker, reject, ahead: null }; // ahead: growAhead's, once the worker knows the vertices
    running = job;
    let memory = null; // the worker's memory coming in slices (after its 'done')
    const finish = () => {
      job.ahead?.stop();
      if (running === job) running = null;
      worker.terminate();
      showFileProgress(null);
      keepFileWorkerReady(); // for the next file
    };
    worker.onmessage = async ({ data }) => {
      if (running !== job) return;
      if (data.type === 'memory-slice') {
        memory?.receive(data);
      } else if (memory && data.type === 'error') {
        memory.fail(new Error(data.message)); // the take-over fails: the page opens the mesh itself
      } else if (data.type === 'progress') {
        // when the page saw it: later than the worker's start when the page's thread was busy
        if (!started) addStage('file worker\'s first message seen (waited for)', 'page', performance.now() - asked);
        started = true;
        showFileProgress(`Reading ${name} (${mb})${data.stage === 'reading' ? '' : `: ${data.stage}`}…`, data.fraction);
        if (instance && data.vertices && !job.ahead) job.ahead = growAhead(instance, data.vertices);
      } else if (data.type === 'done') {
        for (const stage of data.stages ?? []) addStage(stage.stage, stage.thread, stage.ms, stage.bytes ? { bytes: stage.bytes } : {});
        let opened = null;
        if (data.transfer) {
          memory = memorySlicesFrom(worker, data.transfer.memoryBytes);
          job.ahead?.stop(); // what it did not reach, the take-over grows
          await job.ahead?.done;
          if (running !== job) return; // cancelled meanwhile: cancelFileRead rejected already
          try {
            opened = await adopt(data.transfer, {
              memory,
              progress: (f) => showFileProgress(`Reading ${name} (${mb}): taking the editor over…`, 0.95 + 0.05 * f),
              cancelled: () => running !== job,
              instance,
            });
          } catch (e) {
            if (e.cancelled) return; // cancelFileRead rejected already
            throw e;
          }
        }
        finish();
        resolve({ mesh: data.mesh, bytes: new Uint8Array(data.bytes), format: data.format, hierarchy: data.hierarchy, openError: data.openError, opened });
      } else if (data.type === 'error') {
        finish();
        reject(Object.assign(new Error(data.message), { size: Boolean(data.size) }));
      }
    };
    worker.onerror = (e) => {
      e.preventDefault?.();
      if (memory) {
        memory.fail(new Error(e.message || 'the file reader stopped')); // the page opens the mesh itself
        return;
      }
      finish();
      reject(new Error(e.message || 'the file reader could not start'));
    };
    // a stored session's bytes are the app's: the worker gets a copy, handed over (posted without the
    // transfer, it was copied a second time)
    const posted = performance.timeOrigin + performance.now(); // the worker's clock has another origin
    if (file) worker.postMessage({ file, name, editor, posted });
    else {
      const copy = bytes.slice().buffer;
      worker.postMessage({ bytes: copy, name, editor, posted }, [copy]);
    }
  });
}
