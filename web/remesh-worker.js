// Module worker that turns an ordinary closed mesh into a semi-regular one (lib/remesh.mjs; with
// `quads`, a semi-regular quad mesh: lib/remesh-quad.mjs, written with quad faces) off the page's thread.
// Message in:   { mesh: { positions, faces } | text (OBJ), levels? (default: chosen by the remesher), baseFaces?, repair?, keepLargest?, smooth?, quads? }
// Messages out: { type: 'stage', stage }, { type: 'progress', fraction, stage } (the remesher's own: what it
// is doing, 0..1 done), { type: 'done', text, report }, { type: 'error', message }
import { loadMrvol } from './mrvol.js';
import { remesh } from '../lib/remesh.mjs';
import { remeshQuads } from '../lib/remesh-quad.mjs';

self.onmessage = async (event) => {
  const job = event.data;
  try {
    self.postMessage({ type: 'stage', stage: 'loading the core' });
    const mrvol = await loadMrvol();
    self.postMessage({ type: 'stage', stage: `${job.repair ? 'repairing and remeshing' : 'remeshing'}${job.quads ? ' into quads' : ''} (${job.levels ? `${job.levels} levels` : 'levels chosen by the detail'})` });
    const result = await (job.quads ? remeshQuads : remesh)(mrvol, job.mesh ?? mrvol.readObj(job.text), {
      levels: job.levels, baseFaces: job.baseFaces, repair: !!job.repair, keepLargest: !!job.keepLargest, smooth: job.smooth,
      onProgress: (fraction, stage) => self.postMessage({ type: 'progress', fraction, stage }),
    });
    const { mesh, ...report } = result;
    self.postMessage({ type: 'done', text: job.quads ? mrvol.writeObjQuads(mesh) : mrvol.writeObj(mesh), report: { ...report, quads: !!job.quads } });
  } catch (e) {
    self.postMessage({ type: 'error', message: e?.message ?? String(e) });
  }
};
