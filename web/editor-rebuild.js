// A big model's editor at another level or scheme, made in a worker (editor-worker.js) and taken
// over as on opening (file-open.js adopt: the memory copied in slices, the page drawing between
// them), with progress and cancel in the status strip; the session then swaps it in, keeping the
// shape, the reference volume and the undo history (lib/three/session.mjs adoptRebuilt). The
// worker makes the editor the session's settings call for (the limit surface, the centre of mass
// kept, the tensor path's matrix-free editor until theta^e comes: module-transfer.js buildEditor).
// Smaller models and quads are rebuilt on the page's thread: quick, or not this path's to make.
// A big cached theta^e (any model) is read from IndexedDB and given to the editor in the worker too.
import { startBusyJob, endBusyJob, cancelled, adopt, takeFreshInstance, showFileProgress } from './file-open.js';
import { beginStages, addStage, pageStage } from './open-stages.js';
import { memorySlicesFrom } from './memory-slices.js';

// From this many fine vertices the editor is made in the worker (at 164k the polynomial takes ~1 s).
export const WORKER_REBUILD_VERTICES = 100_000;

/**
 * Whether this session's editor at `target` ({ level, scheme }, and maybe { surface, keepCentroid }:
 * a surface switch or its undo) is made in the worker.
 */
export function rebuildsInWorker(session, target) {
  const model = session.model;
  return Boolean(model && session.editor && !session.quad && model.info.vertices >= WORKER_REBUILD_VERTICES &&
    target.scheme !== 'catmull-clark');
}

// From this many bytes a cached theta^e is read and handed to the editor in the worker (the
// dragon sample's θ⁰ is ~320 MB: seconds of reading on the page's thread); smaller ones on the page.
export const WORKER_THETA_BYTES = 16 * 2 ** 20;

/**
 * Whether a cached theta^e of `bytes` for this session's current editor is read in the worker:
 * { worker: true } or { worker: false, why } (words for the readout when it is big but cannot be).
 */
export function thetaInWorker(session, bytes) {
  if (!(bytes >= WORKER_THETA_BYTES)) return { worker: false, why: null };
  if (!session.editor || session.quad) return { worker: false, why: 'a quad mesh\'s editor is not made in the worker' };
  if (session.scheme === 'catmull-clark') return { worker: false, why: 'the editor worker does not make Catmull-Clark editors' };
  return { worker: true };
}

/**
 * Makes the editor at `target` in the worker and hands it to the session (`apply(mr)`: the caller
 * swaps it in). Resolves true when applied, false when cancelled; rejects with the worker's error.
 * With `theta` ({ key }): the worker reads that cached theta^e and makes the editor with it;
 * `apply(mr, thetaInfo)` then gets its info.
 */
export async function rebuildInWorker(session, target, { name, apply, theta = null }) {
  beginStages(`editor at level ${target.level}, ${target.scheme}${theta ? ', θ from the cache' : ''}`);
  const { mr } = session.model;
  const sent = pageStage('mesh, hierarchy and shape copied for the worker', () => ({
    mesh: { positions: mr.positions(), faces: mr.faces() }, hierarchy: mr.hierarchyArrays(), positions: session.positions(),
  }));
  const worker = new Worker(new URL('./editor-worker.js', import.meta.url), { type: 'module', name: 'mrvol-editor' });
  const instance = takeFreshInstance(); // made ahead, or while the worker works
  const surface = target.surface && target.surface !== session.surface ? `, ${target.surface === 'limit' ? 'limit' : 'mesh'} surface` : '';
  const label = `Making the level ${target.level} editor of ${name} (${target.scheme}${surface}${theta ? ', θ from the cache' : ''})`;
  showFileProgress(`${label}…`, 0);
  let job, thetaInfo = null, memory = null; // memory: the worker's, coming in slices after its 'done'
  const transfer = await new Promise((resolve, reject) => {
    job = startBusyJob(worker, () => resolve(null)); // cancelled
    worker.onmessage = ({ data }) => {
      if (cancelled(job)) return;
      if (data.type === 'memory-slice') memory?.receive(data);
      else if (memory && data.type === 'error') memory.fail(new Error(data.message));
      else if (data.type === 'progress') showFileProgress(`${label}: ${data.stage}…`, 0.9 * data.fraction);
      else if (data.type === 'done') {
        for (const s of data.stages) addStage(s.stage, s.thread, s.ms, s.bytes ? { bytes: s.bytes } : {});
        thetaInfo = data.theta;
        memory = memorySlicesFrom(worker, data.transfer.memoryBytes);
        resolve(data.transfer);
      } else {
        endBusyJob(job);
        reject(new Error(data.message));
      }
    };
    worker.onerror = (e) => {
      e.preventDefault?.();
      if (memory) {
        memory.fail(new Error(e.message || 'the editor worker stopped'));
        return;
      }
      endBusyJob(job);
      reject(new Error(e.message || 'the editor worker could not start'));
    };
    const { mesh, hierarchy, positions } = sent;
    const buffers = [mesh.positions.buffer, mesh.faces.buffer, positions.buffer,
      ...['vertexCount', 'coarseFaces', 'ends', 'wings', 'boundary', 'inputIndex'].map((k) => hierarchy[k].buffer)];
    const editor = { level: target.level, scheme: target.scheme, surface: target.surface ?? session.surface,
      keepCentroid: target.keepCentroid ?? session.keepCentroid, path: session.path };
    worker.postMessage({ mesh, hierarchy, positions, editor, theta }, [...new Set(buffers)]);
  });
  if (!transfer) return false;
  let adopted;
  try {
    adopted = await adopt(transfer, {
      memory,
      progress: (f) => showFileProgress(`${label}: taking the editor over…`, 0.9 + 0.1 * f),
      cancelled: () => cancelled(job),
      instance,
    });
  } catch (e) {
    if (e.cancelled) return false;
    throw e;
  }
  endBusyJob(job);
  if (!adopted) throw new Error('the editor made in the worker could not be taken over');
  pageStage('editor swapped in (cage, view)', () => apply(adopted, thetaInfo));
  return true;
}
