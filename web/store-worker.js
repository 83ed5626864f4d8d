// Module worker that writes the editing sessions into IndexedDB (web/session-store.js) off the
// page's thread: cloning a big model's file (tens of MB) and fine positions into the database is
// synchronous where put() is called, a second or more on the page's thread for a 655k-vertex OBJ.
// The page posts the record with its arrays moved here; the reply says whether it was kept.
// Message in:   { id (the page's request number), record (SessionStore.save's argument; model.textStored:
//                 the file is stored already, its bytes not sent) }
// Message out:  { id, ok, problem (plain words, or null), ms (the write, here) }
import { SessionStore } from './session-store.js';

const opening = SessionStore.open();

self.onmessage = async ({ data: { id, record } }) => {
  const store = await opening;
  const started = performance.now();
  const ok = await store.save(record);
  self.postMessage({ id, ok, problem: store.problem, ms: performance.now() - started });
};
