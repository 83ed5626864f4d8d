// Editing sessions in IndexedDB, at any size: one record per model (a sample's name, or an opened
// file's name and size) with its settings, the edited fine positions, the reference volume and the
// undo history; the model file's text and the positions are stored as chunks (web/chunked-store.js).
// The newest record is the session the editor reopens; all of them are the "recent models" list.
// Without IndexedDB every call is a no-op and `problem` says why; a failed write sets `problem`
// (plain words), the next successful one clears it.
import { openDB } from 'idb';
import { putChunks, getChunks, chunkRange, storageProblem, CHUNK_BYTES } from './chunked-store.js';

const DB_NAME = 'mrvol-sessions';
const DB_VERSION = 1;
const OPEN_TIMEOUT_MS = 5000;
const MAX_RECENT = 12;

/**
 * The record id of a model: samples by name, files by name and size; a copy (model.copy: a share
 * link's edits, opened beside the model's own stored ones) has a record of its own.
 */
export function sessionId(model) {
  const id = model.kind === 'sample' ? `sample:${model.name}` : `file:${model.name}:${model.bytes?.byteLength ?? model.text.length}`;
  return model.copy ? `${id}#${model.copy}` : id;
}

export class SessionStore {
  #db = null;
  #textStored = new Set(); // ids whose file text is stored already (it never changes)
  problem = null;

  get available() { return this.#db !== null; }

  static async open() {
    const store = new SessionStore();
    await store.#open();
    return store;
  }

  // The database opened (again: after the browser closed the connection, as clearing the site's data
  // does, the next write opens it anew rather than failing for the rest of the page's life).
  async #open() {
    const store = this;
    try {
      if (typeof indexedDB === 'undefined') throw new Error('IndexedDB is not available in this browser');
      let timer;
      // Two timers in a row: after the page was busy (the core compiling under load) the first one can
      // run before the database's already queued success; the second gives that a turn.
      const timeout = new Promise((_, reject) => {
        timer = setTimeout(() => {
          timer = setTimeout(() => reject(new Error('the browser database did not open in time')), 1000);
        }, OPEN_TIMEOUT_MS);
      });
      store.#db = await Promise.race([openDB(DB_NAME, DB_VERSION, {
        upgrade(db) {
          db.createObjectStore('sessions', { keyPath: 'id' });
          db.createObjectStore('chunks');
        },
        terminated() { store.#closed = true; },
      }), timeout]).finally(() => clearTimeout(timer));
      store.#closed = false;
    } catch (e) {
      store.#db = null;
      store.problem = `sessions are not kept: ${storageProblem(e)}`;
    }
  }

  #closed = false; // the browser closed the connection: reopened before the next write or read
  #reopening = null;

  // Reads after the browser closed the connection (the site's data cleared): the database opened
  // again first, else the recent list stays empty and a model opened again finds none of its edits.
  async #reopened() {
    if (!this.#closed) return;
    this.#reopening ??= this.#open().finally(() => { this.#reopening = null; });
    await this.#reopening;
  }

  /**
   * From now on save() writes in a worker (web/store-worker.js: IndexedDB's cloning of big values
   * off the page's thread); the positions given to save() are moved there (not usable after).
   */
  writeInWorker() {
    if (!this.#db || typeof Worker === 'undefined') return;
    this.#writer = new Worker(new URL('./store-worker.js', import.meta.url), { type: 'module', name: 'mrvol-store' });
    this.#writer.onmessage = ({ data }) => {
      this.#replies.get(data.id)?.(data);
      this.#replies.delete(data.id);
    };
  }

  #writer = null;
  #replies = new Map(); // request number -> resolve
  #requests = 0;
  #lastKept = 0; // the newest request the worker kept
  /** ms of the last write in the worker (for the open stages), or null. */
  lastWorkerMs = null;
  /** How the last save's file reached the worker ({ from: 'file' | 'text' | 'bytes', ms, bytes }), or null. */
  lastFileRead = null;

  #textBytes = new Map(); // id -> the stored file's size in bytes (with #textStored)

  /**
   * What the worker stores of the file, sent once per model, copied nowhere on this thread: the
   * File it was opened from (the worker reads it), or the text (encoded there); only bytes without
   * their File (a project's) are copied here.
   */
  static #fileForWorker(model) {
    if (model.file instanceof Blob && (!model.bytes || model.file.size === model.bytes.byteLength)) return model.file;
    if (model.bytes) return model.bytes.slice();
    return typeof model.text === 'string' ? model.text : undefined;
  }

  /** save() through the worker: the file sent once per model (see #fileForWorker), the positions moved. */
  #saveInWorker(id, { model, settings, fingerprint, positions, reference, history }) {
    const sendText = model.kind === 'file' && !(this.#textStored.has(id) && this.#textBytes.has(id));
    const file = sendText ? SessionStore.#fileForWorker(model) : undefined;
    const record = {
      model: { kind: model.kind, name: model.name, copy: model.copy ?? null, format: model.format, file, textStored: !sendText,
               textBytes: this.#textBytes.get(id) ?? 0, binary: Boolean(model.bytes) },
      settings, fingerprint, positions, reference, history, id,
    };
    const transfer = [file instanceof Uint8Array ? file.buffer : null, positions?.buffer].filter((b) => b instanceof ArrayBuffer);
    const request = ++this.#requests;
    return new Promise((resolve) => {
      this.#replies.set(request, ({ ok, problem, ms, textBytes, fileRead }) => {
        if (ok && model.kind === 'file') {
          this.#textStored.add(id);
          if (Number.isInteger(textBytes)) this.#textBytes.set(id, textBytes);
        }
        // a write that failed before a later one was kept says nothing of the store now
        if (ok || request > this.#lastKept) this.problem = problem;
        if (ok) this.#lastKept = Math.max(this.#lastKept, request);
        this.lastWorkerMs = ms;
        this.lastFileRead = fileRead ?? null;
        resolve(ok);
      });
      try {
        this.#writer.postMessage({ id: request, record }, [...new Set(transfer)]);
      } catch (e) {
        this.#replies.delete(request);
        this.problem = `this session is not kept: ${storageProblem(e)}`;
        resolve(false);
      }
    });
  }

  /**
   * Stores a session: { model: { kind, name, text? | bytes?, format? }, settings, fingerprint, positions: Float64Array,
   * reference, history: { level, scheme, steps } }. Resolves true or false (then `problem` says why).
   * (From the page's worker: the record's id, and model.textStored with textBytes when the file is stored already.)
   */
  async save(session, retried = false) {
    const { model, settings, fingerprint, positions, reference, history, id: given = null } = session;
    if (!this.#db) return false;
    const id = given ?? sessionId(model);
    if (this.#writer) return this.#saveInWorker(id, { model, settings, fingerprint, positions, reference, history });
    if (this.#closed) await this.#open();
    let tx;
    try {
      tx = this.#db.transaction(['sessions', 'chunks'], 'readwrite');
    } catch (e) {
      // a connection the browser is closing (the site's data cleared): opened again, written once more
      if (!retried && e?.name === 'InvalidStateError') {
        await this.#open();
        if (this.#db) return this.save(session, true);
      }
      this.problem = `this session is not kept: ${storageProblem(e)}`;
      return false;
    }
    try {
      const done = tx.done;
      const chunks = tx.objectStore('chunks');
      const record = {
        id, kind: model.kind, name: model.name, copy: model.copy ?? null, settings, fingerprint, reference, history, saved: Date.now(),
        textBytes: null, textChunks: 0, positionCount: 0, positionChunks: 0,
      };
      if (model.kind === 'file' && model.textStored) {
        // written by the page's worker: the file is stored already
        record.format = model.format ?? 'obj';
        record.binary = model.binary;
        record.textBytes = model.textBytes;
        record.textChunks = Math.max(1, Math.ceil(model.textBytes / CHUNK_BYTES));
      } else if (model.kind === 'file') {
        // the file as it was read (any format), or an OBJ text made here (a remeshed model)
        const text = model.bytes ?? new TextEncoder().encode(model.text);
        record.format = model.format ?? 'obj';
        record.binary = model.binary ?? Boolean(model.bytes);
        record.textBytes = text.byteLength;
        if (!this.#textStored.has(id)) {
          chunks.delete(chunkRange(`${id}:text`)).catch(() => {});
          record.textChunks = putChunks(chunks, `${id}:text`, text);
        } else {
          record.textChunks = Math.max(1, Math.ceil(text.byteLength / CHUNK_BYTES));
        }
      }
      if (positions) {
        chunks.delete(chunkRange(`${id}:positions`)).catch(() => {});
        record.positionCount = positions.length;
        record.positionChunks = putChunks(chunks, `${id}:positions`, positions);
      }
      tx.objectStore('sessions').put(record).catch(() => {});
      await done;
      if (model.kind === 'file') this.#textStored.add(id);
      this.problem = null;
      await this.#trim();
      return true;
    } catch (e) {
      try { tx.abort(); } catch { /* already finished */ }
      // the connection closed under this write (the site's data cleared): opened again, written once more
      const error = tx.error ?? e;
      if (!retried && (this.#closed || /closing|closed/i.test(String(error?.message)))) {
        await this.#open();
        if (this.#db) return this.save(session, true);
      }
      this.problem = `this session is not kept: ${storageProblem(error)}`;
      return false;
    }
  }

  /** The newest session (or the one of `id`): { model: { kind, name, text? }, settings, fingerprint, positions, reference, history }, or null. */
  async load(id = null) {
    await this.#reopened();
    if (!this.#db) return null;
    try {
      const record = id ? await this.#db.get('sessions', id) : (await this.recent())[0];
      if (!record) return null;
      const tx = this.#db.transaction('chunks');
      const chunks = tx.objectStore('chunks');
      let text, file;
      if (record.kind === 'file') {
        const bytes = await getChunks(chunks, `${record.id}:text`, record.textChunks);
        if (!bytes || bytes.byteLength !== record.textBytes) return null;
        if (record.binary) file = bytes;
        else text = new TextDecoder().decode(bytes);
        this.#textStored.add(record.id);
        this.#textBytes.set(record.id, record.textBytes);
      }
      let positions = null;
      if (record.positionChunks) {
        const bytes = await getChunks(chunks, `${record.id}:positions`, record.positionChunks);
        if (bytes && bytes.byteLength === 8 * record.positionCount) positions = new Float64Array(bytes.buffer, 0, record.positionCount);
      }
      return {
        model: { kind: record.kind, name: record.name, copy: record.copy ?? null, text, bytes: file, format: record.format },
        settings: record.settings, fingerprint: record.fingerprint, id: record.id,
        positions, reference: record.reference, history: record.history ?? null, saved: record.saved,
      };
    } catch (e) {
      this.problem = `the stored session could not be read: ${storageProblem(e)}`;
      return null;
    }
  }

  /** [{ id, kind, name, saved }], newest first. */
  async recent() {
    await this.#reopened();
    if (!this.#db) return [];
    try {
      const records = await this.#db.getAll('sessions');
      return records.sort((a, b) => b.saved - a.saved);
    } catch {
      return [];
    }
  }

  async remove(id) {
    await this.#reopened();
    if (!this.#db) return;
    try {
      const tx = this.#db.transaction(['sessions', 'chunks'], 'readwrite');
      tx.objectStore('sessions').delete(id);
      tx.objectStore('chunks').delete(chunkRange(`${id}:text`));
      tx.objectStore('chunks').delete(chunkRange(`${id}:positions`));
      await tx.done;
      this.#textStored.delete(id);
      this.#textBytes.delete(id);
    } catch { /* nothing to do */ }
  }

  /** Keeps the MAX_RECENT newest sessions. */
  async #trim() {
    const records = await this.recent();
    for (const record of records.slice(MAX_RECENT)) await this.remove(record.id);
  }
}
