// Module worker that computes the volume tensor theta^e off the page's thread.
//
// Messages in:  { type: 'init', wasm } loads the core ahead of the first job;
//               { type: 'compute', id, meshKey, positions, faces, level, scheme, alpha, beta }
//               ({ wasm } may carry the page's compiled WebAssembly.Module on the first message)
// Messages out: { type: 'progress', id, fraction }
//               { type: 'done', id, bytes: ArrayBuffer (transferred), info, ms, timings }
//               { type: 'error', id, message }
// The page cancels a computation by terminating the worker (the computation is one synchronous
// call into the core; a cancel message could not be read before it returns).
import { loadMrvol } from './mrvol.js';

let opened = null; // { key, mesh }: the last mesh, reused by the next job on the same connectivity

let loading = null;
function api(wasm) {
  loading ??= loadMrvol(wasm).catch((e) => {
    loading = null;
    throw e;
  });
  return loading;
}

function openMesh(m, job) {
  if (opened && opened.key === job.meshKey) return opened.mesh;
  opened?.mesh.delete();
  opened = null;
  const mesh = m.openMesh({ positions: job.positions, faces: job.faces });
  opened = { key: job.meshKey, mesh };
  return mesh;
}

self.onmessage = async (event) => {
  const job = event.data;
  if (job?.type === 'init') {
    api(job.wasm).catch(() => {}); // a failure shows again, with its message, on the first job
    return;
  }
  if (job?.type !== 'compute') return;
  try {
    const received = performance.now();
    const m = await api(job.wasm);
    const loaded = performance.now();
    const mesh = openMesh(m, job);
    const opened = performance.now();
    let last = -1;
    const started = performance.now();
    const theta = mesh.computeTheta({
      level: job.level,
      scheme: job.scheme,
      alpha: job.alpha,
      beta: job.beta,
      storage: 'cage',
      onProgress: (fraction) => {
        if (fraction - last >= 0.01 || fraction >= 1) {
          last = fraction;
          self.postMessage({ type: 'progress', id: job.id, fraction });
        }
        return true;
      },
    });
    const ms = performance.now() - started;
    const info = theta.info();
    let bytes = theta.bytes();
    theta.delete();
    if (bytes.byteOffset !== 0 || bytes.byteLength !== bytes.buffer.byteLength) bytes = bytes.slice();
    const timings = { waitCore: loaded - received, openMesh: opened - loaded, computeTheta: ms, bytes: performance.now() - started - ms };
    self.postMessage({ type: 'done', id: job.id, bytes: bytes.buffer, info, ms, timings }, [bytes.buffer]);
  } catch (e) {
    self.postMessage({ type: 'error', id: job.id, message: e?.message ?? String(e) });
  }
};
