// Values of any size in IndexedDB: Chromium refuses one value over about 133 MB, so bytes are
// split into chunks of CHUNK_BYTES, each its own record under `${key}#${i}`, and read back joined.
// Used by the theta cache and the stored sessions. Errors become plain sentences (storageProblem).

export const CHUNK_BYTES = 32 * 1024 * 1024;

/** A storage failure in plain words, for the readouts. */
export function storageProblem(error) {
  if (!error) return 'the browser could not store it (no reason given)';
  if (error.name === 'QuotaExceededError') return "the browser's storage quota is full (free space or clear the θ cache)";
  if (error.name === 'SecurityError') return 'the browser does not allow storage on this page (private mode or blocked site data)';
  if (error.name === 'DataCloneError') return 'the browser refused a value this large';
  if (error.name === 'UnknownError' || error.name === 'AbortError') return `the browser's database failed to write (${error.message || error.name})`;
  if (error.name === 'Error' && error.message) return error.message; // our own sentences
  return `${error.name ?? 'Error'}: ${error.message ?? String(error)}`;
}

function asBytes(value) {
  if (value instanceof ArrayBuffer) return new Uint8Array(value);
  if (ArrayBuffer.isView(value)) return new Uint8Array(value.buffer, value.byteOffset, value.byteLength);
  throw new TypeError('bytes expected');
}

/** Writes bytes as chunks into `store` (an idb object store of an open readwrite transaction); returns the count. */
export function putChunks(store, key, value) {
  const bytes = asBytes(value);
  const count = Math.max(1, Math.ceil(bytes.byteLength / CHUNK_BYTES));
  if (count === 1 && bytes.byteOffset === 0 && bytes.byteLength === bytes.buffer.byteLength) {
    store.put(bytes.buffer, `${key}#0`).catch(() => {}); // one chunk: no copy
    return 1;
  }
  for (let i = 0; i < count; i++) {
    const chunk = bytes.slice(i * CHUNK_BYTES, Math.min(bytes.byteLength, (i + 1) * CHUNK_BYTES));
    store.put(chunk.buffer, `${key}#${i}`).catch(() => {});
  }
  return count;
}

/**
 * putChunks in turns (issue 13: no long task on the page's thread): one chunk of `chunkBytes` is
 * copied and put at a time, the next only once the last one is written, so the page runs between
 * them (a 335 MB θ put at once held the page's thread for seconds: the copies and the browser's
 * serialization of every chunk in one task). Awaiting the transaction's own requests keeps it
 * open. Resolves to the count; rejects when a put fails (the transaction then aborts).
 */
export async function putChunksInTurns(store, key, value, { chunkBytes = CHUNK_BYTES } = {}) {
  const bytes = asBytes(value);
  const count = Math.max(1, Math.ceil(bytes.byteLength / chunkBytes));
  for (let i = 0; i < count; i++) {
    const chunk = bytes.slice(i * chunkBytes, Math.min(bytes.byteLength, (i + 1) * chunkBytes));
    await store.put(chunk.buffer, `${key}#${i}`);
  }
  return count;
}

/** Reads `count` chunks of key back as one Uint8Array, or null when one is missing. */
export async function getChunks(store, key, count) {
  const parts = await Promise.all(Array.from({ length: count }, (_, i) => store.get(`${key}#${i}`)));
  if (parts.some((p) => !(p instanceof ArrayBuffer))) return null;
  const total = parts.reduce((s, p) => s + p.byteLength, 0);
  const out = new Uint8Array(total);
  let offset = 0;
  for (const p of parts) {
    out.set(new Uint8Array(p), offset);
    offset += p.byteLength;
  }
  return out;
}

/** Every chunk of key (all indices). */
export function chunkRange(key) {
  return IDBKeyRange.bound(`${key}#`, `${key}#\uffff`);
}
