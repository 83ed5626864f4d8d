// Opening a mesh file of any format the core reads (OBJ, STL, PLY, OFF, glTF/GLB): small files are
// parsed here at once, bigger ones in a module worker (open-worker.js) with a progress bar and a
// cancel button in the status strip, so the page keeps drawing while a big file is read.
import { MAX_FILE_BYTES, sizeMessage } from './file-limits.js';
import { loadMrvol } from './mrvol.js';
import { warmUp } from './module-transfer.js';

const $ = (id) => document.getElementById(id);
// Under this size the parse takes well under a frame's worth of waiting; no worker needed.
const WORKER_BYTES = 1_000_000;

let running = null; // { worker, reject }

/** The progress in the status strip: fraction 0..1 (null: indeterminate) and a label; text null hides it. */
export function showFileProgress(text, fraction = null) {
  const box = $('busy');
  box.hidden = text === null;
  $('busy-text').textContent = text ?? '';
  const bar = $('busy-bar');
  if (fraction === null) bar.removeAttribute('value');
  else bar.value = fraction;
}

/** Stops the running read (the cancel button); the promise of readMeshFile rejects with { cancelled }. */
export function cancelFileRead() {
  if (!running) return false;
  const { worker, reject } = running;
  running = null;
  worker.terminate();
  showFileProgress(null);
  reject(Object.assign(new Error('cancelled'), { cancelled: true }));
  return true;
}

/**
 * The worker's mesh and editor in a fresh instance of the module (module-transfer.js): the
 * MultiresMesh, whose first createEditor at the worker's level and scheme is the editor made
 * there; null when that fails (the page then opens the mesh from the hierarchy arrays).
 */
async function adopt(transfer) {
  try {
    const fresh = await loadMrvol();
    warmUp(fresh);
    return fresh.adoptTransferred(transfer);
  } catch (e) {
    console.warn(`the worker's editor could not be taken over (${e.message}): opening the mesh here`);
    return null;
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
  const worker = new Worker(new URL('./open-worker.js', import.meta.url), { type: 'module', name: 'mrvol-open' });
  const mb = `${(size / 1e6).toFixed(1)} MB`;
  showFileProgress(`Reading ${name} (${mb})…`, 0);
  return new Promise((resolve, reject) => {
    const job = { worker, reject };
    running = job;
    const finish = () => {
      if (running === job) running = null;
      worker.terminate();
      showFileProgress(null);
    };
    worker.onmessage = async ({ data }) => {
      if (running !== job) return;
      if (data.type === 'progress') {
        showFileProgress(`Reading ${name} (${mb})${data.stage === 'reading' ? '' : `: ${data.stage}`}…`, data.fraction);
      } else if (data.type === 'done') {
        finish();
        resolve({ mesh: data.mesh, bytes: new Uint8Array(data.bytes), format: data.format, hierarchy: data.hierarchy, openError: data.openError,
                  opened: data.transfer ? await adopt(data.transfer) : null });
      } else if (data.type === 'error') {
        finish();
        reject(Object.assign(new Error(data.message), { size: Boolean(data.size) }));
      }
    };
    worker.onerror = (e) => {
      e.preventDefault?.();
      finish();
      reject(new Error(e.message || 'the file reader could not start'));
    };
    // a stored session's bytes are the app's: the worker gets a copy
    worker.postMessage(file ? { file, name, editor } : { bytes: bytes.slice().buffer, name, editor });
  });
}
