// IndexedDB cache of theta files (the bytes theta.bytes() gives), keyed by what theta depends on:
// `${fingerprint}:${scheme}:${alpha}:${beta}:${level}:v1`, the fingerprint being the mesh's
// connectivity. Editing positions never invalidates an entry, and another model with the same
// connectivity reuses it.
//
// Two stores written in one transaction: 'theta' (`${key}#${i}` -> ArrayBuffer chunks of 4 MB (earlier entries: 32 MB),
// web/chunked-store.js: one value over ~133 MB is refused by Chromium) and 'theta-meta' (key ->
// { key, bytes, chunks, model, created }), so that listing entries does not read the tensors.
// Without IndexedDB (private modes, blocked storage) every call is a no-op and `available` is false.
import { openDB, deleteDB } from 'idb';
import { putChunksInTurns, getChunks, chunkRange, storageProblem } from './chunked-store.js';

const DB_NAME = 'mrvol';
const DB_VERSION = 1;
const OPEN_TIMEOUT_MS = 5000;
// A θ is written in chunks of this size, one a task (putChunksInTurns): each chunk's copy and
// serialization on the page's thread stays well under 100 ms on a loaded machine. Read back whatever
// size they were written in (the entry's chunk count).
const WRITE_CHUNK_BYTES = 4 * 2 ** 20;

export function thetaKey({ fingerprint, scheme, alpha, beta, level }) {
  return `${fingerprint}:${scheme}:${alpha}:${beta}:${level}:v1`;
}

const describe = storageProblem;

export class ThetaCache {
  #db = null;
  /** Why the cache is off, when it is. */
  reason = null;

  get available() { return this.#db !== null; }

  static async open() {
    const cache = new ThetaCache();
    try {
      if (typeof indexedDB === 'undefined') throw new Error('IndexedDB is not available in this browser');
      const opening = openDB(DB_NAME, DB_VERSION, {
        upgrade(db) {
          if (!db.objectStoreNames.contains('theta')) db.createObjectStore('theta');
          if (!db.objectStoreNames.contains('theta-meta')) db.createObjectStore('theta-meta', { keyPath: 'key' });
        },
        blocked() { /* another tab holds an older version: the timeout below gives up */ },
      });
      let timer;
      // Two timers in a row: after the page was busy (the core compiling under load) the first one can
      // run before the database's already queued success; the second gives that a turn.
      const timeout = new Promise((_, reject) => {
        timer = setTimeout(() => {
          timer = setTimeout(() => reject(new Error('IndexedDB did not open in time')), 1000);
        }, OPEN_TIMEOUT_MS);
      });
      cache.#db = await Promise.race([opening, timeout]).finally(() => clearTimeout(timer));
      cache.#db.addEventListener?.('close', () => {
        cache.#db = null;
        cache.reason = 'the browser closed the database';
      });
    } catch (e) {
      cache.#db = null;
      cache.reason = describe(e);
    }
    return cache;
  }

  /** The size in bytes of the cached theta file (its listing alone, no tensor read), or null. */
  async size(key) {
    if (!this.#db) return null;
    try {
      return (await this.#db.get('theta-meta', key))?.bytes ?? null;
    } catch {
      return null;
    }
  }

  /** The cached theta file, or null. */
  async get(key) {
    if (!this.#db) return null;
    try {
      const tx = this.#db.transaction(['theta', 'theta-meta']);
      const meta = await tx.objectStore('theta-meta').get(key);
      if (!meta) return null;
      const bytes = Number.isInteger(meta.chunks) ? await getChunks(tx.objectStore('theta'), key, meta.chunks) : null;
      if (bytes) return bytes; // the core checks them; theta-source drops an unusable entry
      await this.delete(key); // a chunk is missing: drop it
      return null;
    } catch {
      return null;
    }
  }

  /**
   * Stores a theta file. Resolves to { ok: true } or { ok: false, reason } (quota exceeded, which
   * arrives as a transaction abort, or any other failure); never rejects.
   */
  async put(key, bytes, meta = {}) {
    if (!this.#db) return { ok: false, reason: this.reason ?? 'no IndexedDB' };
    const buffer = bytes instanceof ArrayBuffer ? bytes
      : bytes.byteOffset === 0 && bytes.byteLength === bytes.buffer.byteLength ? bytes.buffer : bytes.slice().buffer;
    let tx;
    try {
      tx = this.#db.transaction(['theta', 'theta-meta'], 'readwrite');
      // done rejects on 'abort' as well as 'error' (a quota error aborts the transaction).
      const done = tx.done;
      done.catch(() => {}); // awaited below, or the failure is said from tx.error
      tx.objectStore('theta').delete(chunkRange(key)).catch(() => {});
      const chunks = await putChunksInTurns(tx.objectStore('theta'), key, buffer, { chunkBytes: WRITE_CHUNK_BYTES });
      tx.objectStore('theta-meta').put({ key, bytes: buffer.byteLength, chunks, created: Date.now(), ...meta }).catch(() => {});
      await done;
      return { ok: true };
    } catch (e) {
      try { tx?.abort(); } catch { /* already finished */ }
      return { ok: false, reason: describe(tx?.error ?? e) };
    }
  }

  async delete(key) {
    if (!this.#db) return;
    try {
      const tx = this.#db.transaction(['theta', 'theta-meta'], 'readwrite');
      tx.objectStore('theta').delete(chunkRange(key));
      tx.objectStore('theta-meta').delete(key);
      await tx.done;
    } catch { /* nothing to do */ }
  }

  /** [{ key, bytes, model, created }], newest first. */
  async list() {
    if (!this.#db) return [];
    try {
      const entries = await this.#db.getAll('theta-meta');
      return entries.sort((a, b) => (b.created ?? 0) - (a.created ?? 0));
    } catch {
      return [];
    }
  }

  async clear() {
    if (!this.#db) return;
    try {
      const tx = this.#db.transaction(['theta', 'theta-meta'], 'readwrite');
      tx.objectStore('theta').clear();
      tx.objectStore('theta-meta').clear();
      await tx.done;
    } catch {
      // A broken database: start over.
      this.#db.close();
      this.#db = null;
      await deleteDB(DB_NAME).catch(() => {});
    }
  }
}
