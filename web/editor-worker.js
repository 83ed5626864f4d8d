// Module worker that makes a big model's editor at another level or scheme off the page's thread
// (issue 13: "no long computation or hand-off on the main thread"). It opens the mesh from the
// hierarchy the page's mesh has (no detection again: a few linear passes), sets the current shape,
// makes the editor the page's session would make (module-transfer.js buildEditor: the cage
// polynomial, the limit surface's form, the kept centre of mass's moments) and hands over its
// module's memory a slice at a time as the page asks (memory-slices.js), as the file's worker does on opening. With `theta` (a key of the θ cache) it
// reads theta^e from IndexedDB here and hands it to the editor (the tensor path: the editor keeps
// the cage polynomial contracted from it, so θ itself is freed before the copy).
// Message in:   { mesh: { positions, faces }, hierarchy (MultiresMesh.hierarchyArrays()), positions (the shape now),
//                editor: { level, scheme, surface, keepCentroid, path } (the session's settings), theta?: { key } }
//               then { type: 'memory-slice', buffer? } (memory-slices.js) after the 'done'
// Messages out: { type: 'progress', stage, fraction }, { type: 'done', transfer, stages, theta (its info) },
//               { type: 'memory-slice', bytes, ms }, { type: 'error', message }
import { loadMrvol } from './mrvol.js';
import { warmUp, buildEditor } from './module-transfer.js';
import { workerStages } from './open-stages.js';
import { memorySliceServer } from './memory-slices.js';
import { ThetaCache } from './theta-cache.js';

// the time of each stage here (sent with the result)
const { list: stages, timed, add } = workerStages();

/** The cached θ file of `key`, read here (IndexedDB in the worker); throws when it is not there. */
async function cachedTheta(key) {
  const started = performance.now();
  const cache = await ThetaCache.open();
  if (!cache.available) throw new Error(`no θ cache in the editor worker (${cache.reason})`);
  const bytes = await cache.get(key);
  if (!bytes) throw new Error('θ is no longer in the cache');
  add('θ read from the cache (IndexedDB)', performance.now() - started, { bytes: bytes.byteLength });
  return bytes;
}

let sendSlice = null; // after the 'done': answers the page's asks for its memory

self.onmessage = async ({ data }) => {
  if (data.type === 'memory-slice') {
    try {
      sendSlice(data);
    } catch (e) {
      self.postMessage({ type: 'error', message: e?.message ?? String(e) });
    }
    return;
  }
  const { mesh, hierarchy, positions, editor: settings, theta: wanted } = data;
  try {
    self.postMessage({ type: 'progress', stage: 'starting', fraction: 0 });
    const reading = wanted ? cachedTheta(wanted.key) : null;
    reading?.catch(() => {}); // awaited below
    const mrvol = await loadMrvol();
    timed('core warmed up', () => warmUp(mrvol));
    self.postMessage({ type: 'progress', stage: 'opening the mesh', fraction: 0.1 });
    const mr = timed('mesh opened (the page\'s hierarchy)', () => mrvol.openMeshWithHierarchy(mesh, hierarchy));
    mr.setPositions(positions);
    self.postMessage({ type: 'progress', stage: 'making the editor', fraction: 0.2 });
    const editor = timed('editor made', () => buildEditor(mrvol, mr, settings));
    let thetaInfo = null;
    if (reading) {
      self.postMessage({ type: 'progress', stage: 'reading θ from the cache', fraction: 0.3 });
      const bytes = await reading;
      const theta = timed('θ read (readTheta)', () => mrvol.readTheta(bytes));
      try {
        thetaInfo = theta.info();
        self.postMessage({ type: 'progress', stage: 'handing θ to the editor', fraction: 0.6 });
        timed('editor made with θ (useTheta)', () => editor.useTheta(theta));
      } finally {
        theta.delete(); // the editor keeps the polynomial contracted from it
      }
    }
    self.postMessage({ type: 'progress', stage: 'handing the editor over', fraction: 0.9 });
    // the memory itself goes in slices once the page asks: nothing runs here meanwhile
    const transfer = mrvol.transferable(mr, editor, { scheme: settings.scheme, memory: false });
    sendSlice = memorySliceServer(mrvol, transfer.memoryBytes);
    self.postMessage({ type: 'done', transfer, stages, theta: thetaInfo }, [transfer.positions.buffer]);
  } catch (e) {
    self.postMessage({ type: 'error', message: e?.message ?? String(e) });
  }
};
