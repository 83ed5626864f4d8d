// Module worker that turns an ordinary closed mesh into a semi-regular one (lib/remesh.mjs) off
// the page's thread.
// Message in:   { text, levels, baseFaces? }
// Messages out: { type: 'stage', stage }, { type: 'done', text, report }, { type: 'error', message }
import { loadMrvol } from './mrvol.js';
import { remesh } from '../lib/remesh.mjs';

self.onmessage = async (event) => {
  const job = event.data;
  try {
    self.postMessage({ type: 'stage', stage: 'loading the core' });
    const mrvol = await loadMrvol();
    self.postMessage({ type: 'stage', stage: `remeshing (${job.levels} levels)` });
    const result = await remesh(mrvol, mrvol.readObj(job.text), { levels: job.levels, baseFaces: job.baseFaces });
    const { mesh, ...report } = result;
    self.postMessage({ type: 'done', text: mrvol.writeObj(mesh), report });
  } catch (e) {
    self.postMessage({ type: 'error', message: e?.message ?? String(e) });
  }
};
