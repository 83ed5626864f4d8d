// Module worker that writes the editing sessions into IndexedDB (web/session-store.js) off the
// page's thread: cloning a big model's file (tens of MB) and fine positions into the database is
// synchronous where put() is called, a second or more on the page's thread for a 655k-vertex OBJ.
// The page posts the record with its arrays moved here; the reply says whether it was kept.
// The file itself comes once per model as the File it was opened from (read here) or its text
// (encoded here), so the page copies nothing of it.
// Message in:   { id (the page's request number), record (SessionStore.save's argument, with model.file: a
//                 Blob, bytes or text; model.textStored: the file is stored already, nothing sent) }
// Message out:  { id, ok, problem (plain words, or null), ms (the write, here), textBytes (the file's size stored),
//                fileRead: { from: 'file' | 'text' | 'bytes', ms, bytes } when the file came with this save, else null }
import { SessionStore } from './session-store.js';
import { storageProblem } from './chunked-store.js';

const opening = SessionStore.open();

/** The record's file as bytes (read or encoded here). */
async function fileBytes(file) {
  if (file instanceof Blob) return new Uint8Array(await file.arrayBuffer());
  return typeof file === 'string' ? new TextEncoder().encode(file) : file;
}

self.onmessage = async ({ data: { id, record } }) => {
  const store = await opening;
  const started = performance.now();
  const { file, ...model } = record.model;
  let bytes, fileRead = null;
  try {
    bytes = file === undefined ? undefined : await fileBytes(file);
    if (bytes) fileRead = { from: file instanceof Blob ? 'file' : typeof file === 'string' ? 'text' : 'bytes', ms: performance.now() - started, bytes: bytes.byteLength };
  } catch (e) {
    const problem = `this session is not kept: the file could not be read again (${storageProblem(e)})`;
    self.postMessage({ id, ok: false, problem, ms: performance.now() - started });
    return;
  }
  // binary as the page said: a text file's bytes are stored as text (decoded when loaded)
  let ok = false;
  try {
    ok = await store.save({ ...record, model: bytes ? { ...model, bytes } : model });
  } catch (e) {
    // never left without a reply: the page says what went wrong instead of waiting for ever
    store.problem = `this session is not kept: ${storageProblem(e)}`;
  }
  const textBytes = bytes?.byteLength ?? (model.textStored ? model.textBytes : undefined);
  self.postMessage({ id, ok, problem: store.problem, ms: performance.now() - started, textBytes, fileRead });
};
