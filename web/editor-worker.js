// Module worker that makes a big model's editor at another level or scheme off the page's thread
// (issue 13: "no long computation or hand-off on the main thread"). It opens the mesh from the
// hierarchy the page's mesh has (no detection again: a few linear passes), sets the current shape,
// makes the editor the page's session would make (module-transfer.js buildEditor: the cage
// polynomial, the limit surface's form, the kept centre of mass's moments) and hands over a copy of
// its module's memory, as the file's worker does on opening.
// Message in:   { mesh: { positions, faces }, hierarchy (MultiresMesh.hierarchyArrays()), positions (the shape now),
//                editor: { level, scheme, surface, keepCentroid, path } (the session's settings) }
// Messages out: { type: 'progress', stage, fraction }, { type: 'done', transfer, stages }, { type: 'error', message }
import { loadMrvol } from './mrvol.js';
import { warmUp, buildEditor } from './module-transfer.js';
import { workerStages } from './open-stages.js';

// the time of each stage here (sent with the result)
const { list: stages, timed } = workerStages();

self.onmessage = async ({ data: { mesh, hierarchy, positions, editor: settings } }) => {
  try {
    self.postMessage({ type: 'progress', stage: 'starting', fraction: 0 });
    const mrvol = await loadMrvol();
    timed('core warmed up', () => warmUp(mrvol));
    self.postMessage({ type: 'progress', stage: 'opening the mesh', fraction: 0.1 });
    const mr = timed('mesh opened (the page\'s hierarchy)', () => mrvol.openMeshWithHierarchy(mesh, hierarchy));
    mr.setPositions(positions);
    self.postMessage({ type: 'progress', stage: 'making the editor', fraction: 0.2 });
    const editor = timed('editor made', () => buildEditor(mrvol, mr, settings));
    self.postMessage({ type: 'progress', stage: 'handing the editor over', fraction: 0.9 });
    const transfer = timed('memory copied for the page', () => mrvol.transferable(mr, editor, { scheme: settings.scheme }));
    stages.at(-1).bytes = transfer.memory.byteLength;
    self.postMessage({ type: 'done', transfer, stages }, [transfer.memory.buffer, transfer.positions.buffer]);
  } catch (e) {
    self.postMessage({ type: 'error', message: e?.message ?? String(e) });
  }
};
