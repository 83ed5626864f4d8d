// A small copy of the editing session in localStorage, which the teaching views read synchronously:
// the model (a sample's name, or an opened file's name and text when it fits), the settings, the
// edited fine positions (when they fit) and the reference volume. The editor keeps the whole session
// at any size in IndexedDB (web/session-store.js) and falls back to this copy without it.
// Storage failures (quota, disabled storage) only mean no copy is kept.
const KEY = 'mrvol.session.v1';
const MAX_TEXT = 3_000_000; // characters of an opened OBJ file kept here (web/session-store.js keeps any size)
const MAX_POSITIONS = 200_000; // numbers of edited positions kept here

export function encodeFloat64(array) {
  const bytes = new Uint8Array(array.buffer, array.byteOffset, array.byteLength);
  let binary = '';
  for (let i = 0; i < bytes.length; i += 0x8000) binary += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(binary);
}

export function decodeFloat64(text) {
  const binary = atob(text);
  if (binary.length % 8 !== 0) throw new Error('bad length');
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  return new Float64Array(bytes.buffer);
}

/** The stored session, or null. */
export function loadSession() {
  try {
    const text = localStorage.getItem(KEY);
    if (!text) return null;
    const session = JSON.parse(text);
    if (session?.version !== 1 || !session.model?.name) return null;
    return session;
  } catch {
    return null;
  }
}

/**
 * Stores { model: { kind, name, text? }, settings, fingerprint, positions: Float64Array | null,
 * reference }. Returns false when it could not be stored.
 */
export function saveSession({ model, settings, fingerprint, positions, reference }) {
  const stored = {
    version: 1,
    model: { kind: model.kind, name: model.name, ...(model.copy ? { copy: model.copy } : {}) },
    settings,
    fingerprint,
    positions: positions && positions.length <= MAX_POSITIONS ? encodeFloat64(positions) : null,
    reference,
    saved: Date.now(),
  };
  // an OBJ opened from its bytes: its text when small (the teaching views read OBJ text)
  const text = model.text ?? (model.format === 'obj' && model.bytes?.byteLength <= MAX_TEXT ? new TextDecoder().decode(model.bytes) : undefined);
  if (model.kind === 'file' && typeof text === 'string' && text.length <= MAX_TEXT) stored.model.text = text;
  try {
    localStorage.setItem(KEY, JSON.stringify(stored));
    return true;
  } catch {
    // Too big with the file text: keep at least the settings.
    try {
      delete stored.model.text;
      stored.positions = null;
      localStorage.setItem(KEY, JSON.stringify(stored));
    } catch { /* storage off */ }
    return false;
  }
}

export function clearSession() {
  try {
    localStorage.removeItem(KEY);
  } catch { /* storage off */ }
}

/**
 * The model of the stored session, for other views (the teaching views): { kind, name, text (an
 * opened file's, else null), positions (the edited fine positions, or null) }, or null. They need
 * not know how the session is stored.
 */
export function storedModel() {
  const session = loadSession();
  if (!session) return null;
  let positions = null;
  try {
    positions = session.positions ? decodeFloat64(session.positions) : null;
  } catch { /* a damaged session: the file's own positions */ }
  const { kind, name, text } = session.model;
  return { kind, name, text: typeof text === 'string' ? text : null, positions };
}
