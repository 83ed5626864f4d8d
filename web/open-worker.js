// Module worker that reads a mesh file off the page's thread: the bytes in chunks (progress as it
// goes), then the core's reader for its format (lib/api.mjs readMesh: OBJ, STL, PLY, OFF, glTF/GLB)
// through the package's browser entry (web/mrvol.js: compiled here, not handed over by the page,
// which measurably blocked the page's thread for a moment); then validation and hierarchy
// detection (models.js openParsed), the slow part of opening a big mesh. The page opens the parsed
// arrays with the hierarchy found here (web/file-open.js; MultiresMesh.hierarchyArrays and
// openMeshWithHierarchy): a few linear passes on its thread instead of seconds. Asked for an editor
// ({ level, scheme }: the page's settings), it makes that too, the slowest part (the cage
// polynomial), and hands over its module's memory for the page to take (module-transfer.js), a
// slice at a time as the page asks (memory-slices.js); the hierarchy stays the fallback.
// Message in:   { file?: File, bytes?: ArrayBuffer, name, editor?: { level, scheme, positions? (a stored session's) },
//                 posted? (performance.timeOrigin + now() on the page: how long the job waited for the worker) },
//               then { type: 'memory-slice', buffer? } (memory-slices.js) after a 'done' with a transfer
// Messages out: { type: 'progress', stage, fraction, vertices? (once parsed) },
//               { type: 'done', mesh, bytes, format, hierarchy, transfer (lib/api.mjs transferable, its memory
//                 sent in slices) | null, openError: { message, offer } | null, stages: [{ stage, thread, ms }] (web/open-stages.js) },
//               { type: 'memory-slice', bytes, ms }, { type: 'error', message, size? (true: a size problem) }
import { loadMrvol } from './mrvol.js';
import { claimedVertices, MAX_VERTICES, sizeMessage } from './file-limits.js';
import { openParsed } from './models.js';
import { warmUpInSteps, buildEditor } from './module-transfer.js';
import { workerStages } from './open-stages.js';
import { memorySliceServer } from './memory-slices.js';

const outOfMemory = (e) => e instanceof RangeError || /memory|bad_alloc/i.test(e?.message ?? '');

const post = (message, transfer = []) => self.postMessage(message, transfer);

// the time of each stage here (sent with the result)
const { list: stages, add: addStage, timed } = workerStages();

/** The file's bytes, read in chunks with progress (a File's stream; `bytes` as they are). */
async function readBytes(file) {
  const bytes = new Uint8Array(file.size);
  const reader = file.stream().getReader();
  let at = 0, said = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    if (at + value.byteLength > bytes.byteLength) throw new Error('the file grew while it was read');
    bytes.set(value, at);
    at += value.byteLength;
    if (at - said > bytes.byteLength / 50) {
      said = at;
      post({ type: 'progress', stage: 'reading', fraction: 0.5 * at / bytes.byteLength });
    }
  }
  return at === bytes.byteLength ? bytes : bytes.subarray(0, at);
}

/**
 * The page's first editor made here and the module's memory to hand over (lib/api.mjs
 * transferable), or null when that does not work out (memory, say): the page then makes the editor.
 */
function editorTransfer(mrvol, mr, info, mesh, { level, scheme, positions, surface, keepCentroid, path }) {
  post({ type: 'progress', stage: 'making the editor', fraction: 0.8 });
  // a stored session's shape (the page sets it again: the same values keep this editor)
  if (positions instanceof Float64Array && positions.length === mesh.positions.length) {
    try {
      mr.setPositions(positions);
    } catch { /* not a shape of this mesh: the page says so */ }
  }
  try {
    const editor = timed('editor made', () => buildEditor(mrvol, mr, { level: Math.min(level, info.levels), scheme, surface, keepCentroid, path }));
    post({ type: 'progress', stage: 'handing the editor over', fraction: 0.95 });
    // the memory itself goes in slices once the page asks (memorySliceServer): nothing runs here meanwhile
    return mrvol.transferable(mr, editor, { scheme, memory: false });
  } catch {
    return null; // the page makes the editor itself, and says what is wrong if anything is
  }
}

// The core loaded and warmed up as soon as the worker starts, as the page's instance will be before
// it takes the copy: the page starts one worker ahead of any file (file-open.js), so a dropped
// file's reading and parsing need not wait for the worker's script and core. The warm-up yields
// between its steps: a file dropped meanwhile is read at once, beside it (its parse awaits it).
const mrvolLoading = loadMrvol().then(async (mrvol) => {
  await warmUpInSteps(mrvol, () => new Promise((resolve) => setTimeout(resolve, 0)));
  return mrvol;
});
mrvolLoading.catch(() => {}); // awaited by the job

let sendSlice = null; // after a 'done' with a transfer: answers the page's asks for its memory

self.onmessage = async ({ data: job }) => {
  if (job.type === 'memory-slice') {
    try {
      sendSlice(job);
    } catch (e) {
      post({ type: 'error', message: e?.message ?? String(e) });
    }
    return;
  }
  try {
    if (Number.isFinite(job.posted)) addStage('file worker started (after the page posted the file)', performance.timeOrigin + performance.now() - job.posted);
    post({ type: 'progress', stage: 'reading', fraction: 0 });
    const reading = performance.now();
    const bytes = job.file ? await readBytes(job.file) : new Uint8Array(job.bytes);
    addStage('file read', performance.now() - reading, { bytes: bytes.byteLength });
    const claimed = claimedVertices(bytes, job.name);
    if (claimed > MAX_VERTICES) {
      post({ type: 'error', message: sizeMessage({ vertices: claimed, claimed: true }), size: true });
      return;
    }
    const waiting = performance.now();
    const mrvol = await mrvolLoading;
    addStage('core loaded (waited for)', performance.now() - waiting);
    const format = mrvol.detectFormat(bytes, job.name);
    post({ type: 'progress', stage: `parsing the ${format.toUpperCase()} file`, fraction: 0.5 });
    let mesh;
    try {
      mesh = timed('file parsed', () => mrvol.readMesh(bytes, { name: job.name }));
    } catch (e) {
      // The core ran out of memory (a WebAssembly heap of at most a few GB): say so in terms of size.
      if (outOfMemory(e)) {
        post({ type: 'error', message: sizeMessage({ bytes: bytes.byteLength }), size: true });
        return;
      }
      throw e;
    }
    const vertices = mesh.positions.length / 3;
    if (vertices > MAX_VERTICES) {
      post({ type: 'error', message: sizeMessage({ vertices }), size: true });
      return;
    }
    post({ type: 'progress', stage: 'finding its levels', fraction: 0.7, vertices }); // the page grows its memory ahead (file-open.js)
    // What the page would find on its thread: the hierarchy, or why the mesh does not open (the
    // page shows it and offers a remesh with the mesh itself).
    let hierarchy = null, openError = null, transfer = null;
    try {
      const { mr, info } = timed('validated, levels found', () => openParsed(mrvol, mesh));
      hierarchy = mr.hierarchyArrays();
      if (job.editor) transfer = editorTransfer(mrvol, mr, info, mesh, job.editor);
      // nothing is deleted: the copy of the memory holds them; the worker ends after this message
    } catch (e) {
      if (outOfMemory(e)) {
        post({ type: 'error', message: sizeMessage({ vertices }), size: true });
        return;
      }
      openError = { message: e.message, offer: e.offer ?? null };
    }
    post({ type: 'progress', stage: 'handing the mesh over', fraction: 0.95 });
    const buffers = [mesh.positions.buffer, mesh.faces.buffer];
    if (hierarchy)
      for (const key of ['vertexCount', 'coarseFaces', 'ends', 'wings', 'boundary', 'inputIndex']) buffers.push(hierarchy[key].buffer);
    if (transfer) buffers.push(transfer.positions.buffer);
    for (const key of ['texCoords', 'normals', 'colors', 'cornerTexCoords', 'cornerNormals', 'sourceVertex'])
      if (ArrayBuffer.isView(mesh[key])) buffers.push(mesh[key].buffer);
    if (mesh.lines) buffers.push(mesh.lines.vertex.buffer, mesh.lines.face.buffer);
    const copy = { ...mesh };
    if (transfer) sendSlice = memorySliceServer(mrvol, transfer.memoryBytes, post);
    post({ type: 'done', mesh: copy, bytes: bytes.buffer, format, hierarchy, transfer, openError, stages }, [...new Set(buffers.filter((b) => b !== bytes.buffer)), bytes.buffer]);
  } catch (e) {
    post({ type: 'error', message: e?.message ?? String(e) });
  }
};
