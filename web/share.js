// Sharing an edited model: a link (a sample's name, the settings and the edit as the difference of
// the fine positions from the sample's own, float32, deflated, base64url, in `?edits=`) and a
// project file (JSON: the model's OBJ text or its file's bytes, the edited positions, the reference
// volume, the settings). Both restore the shape through the same path as a stored session.

const PROJECT_FORMAT = 'mrvol-project';
const PROJECT_VERSION = 1;

// base64url by table, into bytes: a project holds the file and the positions this way (tens of MB
// for a big model: String.fromCharCode and btoa took seconds there, and JSON.stringify and the Blob's
// UTF-8 encoding of the result as much again).
const ALPHABET = 'ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_';
const CODE_OF = new Uint8Array(64).map((_, i) => ALPHABET.charCodeAt(i));
// Two letters per 12 bits, as the two bytes of a little-endian Uint16: three bytes become one Uint32.
const LITTLE_ENDIAN = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;
const PAIR_OF = new Uint16Array(4096).map((_, i) => CODE_OF[i >>> 6] | CODE_OF[i & 63] << 8);
// A letter's 6 bits in place for each of the four positions of a group; not a letter: the sign bit,
// so that one test of the four OR-ed finds any. base64's own '+' and '/' are read too.
const BITS_AT = [18, 12, 6, 0].map((shift) => {
  const table = new Int32Array(128).fill(-0x80000000);
  for (let i = 0; i < 64; i++) table[ALPHABET.charCodeAt(i)] = i << shift;
  table[43] = 62 << shift; // '+'
  table[47] = 63 << shift; // '/'
  return table;
});

/** The base64url spelling (no padding) of bytes, as ASCII bytes. */
export function base64UrlBytes(bytes) {
  const n = bytes.length, whole = n - n % 3, groups = whole / 3;
  const length = Math.ceil(4 * n / 3);
  const out = new Uint8Array(new ArrayBuffer(4 * Math.ceil(length / 4)), 0, length);
  if (LITTLE_ENDIAN) {
    const out32 = new Uint32Array(out.buffer, 0, groups);
    for (let g = 0, i = 0; g < groups; g++, i += 3) {
      const v = bytes[i] << 16 | bytes[i + 1] << 8 | bytes[i + 2];
      out32[g] = PAIR_OF[v >>> 12] | PAIR_OF[v & 4095] << 16;
    }
  } else {
    for (let g = 0, i = 0; g < groups; g++, i += 3) {
      const v = bytes[i] << 16 | bytes[i + 1] << 8 | bytes[i + 2];
      out[4 * g] = CODE_OF[v >>> 18];
      out[4 * g + 1] = CODE_OF[v >>> 12 & 63];
      out[4 * g + 2] = CODE_OF[v >>> 6 & 63];
      out[4 * g + 3] = CODE_OF[v & 63];
    }
  }
  if (n > whole) {
    const o = 4 * groups;
    const v = bytes[whole] << 16 | (n - whole === 2 ? bytes[whole + 1] << 8 : 0);
    out[o] = CODE_OF[v >>> 18];
    out[o + 1] = CODE_OF[v >>> 12 & 63];
    if (n - whole === 2) out[o + 2] = CODE_OF[v >>> 6 & 63];
  }
  return out;
}

function toBase64Url(bytes) {
  return new TextDecoder().decode(base64UrlBytes(bytes));
}

/** The bytes of a base64url (or base64) text; throws a sentence naming `what` and where it is not. */
export function fromBase64Url(text, what = 'the text') {
  let n = text.length;
  while (n > 0 && text.charCodeAt(n - 1) === 61) n--; // '=' padding
  if (n % 4 === 1) throw new Error(`${what} is not base64 (its length, ${n}, is one more than a multiple of 4)`);
  const [at18, at12, at6, at0] = BITS_AT;
  const whole = n - n % 4;
  const out = new Uint8Array(Math.floor(3 * n / 4));
  const wrong = (from) => {
    for (let i = from; i < n; i++) {
      const c = text.charCodeAt(i);
      if (c >= 128 || at0[c] < 0) return new Error(`${what} is not base64: character ${i + 1} is ${JSON.stringify(text[i])}`);
    }
    return new Error(`${what} is not base64`);
  };
  for (let i = 0, o = 0; i < whole; i += 4, o += 3) {
    const c0 = text.charCodeAt(i), c1 = text.charCodeAt(i + 1), c2 = text.charCodeAt(i + 2), c3 = text.charCodeAt(i + 3);
    const v = (c0 | c1 | c2 | c3) < 128 ? at18[c0] | at12[c1] | at6[c2] | at0[c3] : -1;
    if (v < 0) throw wrong(i);
    out[o] = v >>> 16;
    out[o + 1] = v >>> 8 & 255;
    out[o + 2] = v & 255;
  }
  if (n > whole) {
    const c = [0, 1, 2].map((k) => (whole + k < n ? text.charCodeAt(whole + k) : 65)); // 'A': 0 bits
    const v = (c[0] | c[1] | c[2]) < 128 ? at18[c[0]] | at12[c[1]] | at6[c[2]] : -1;
    if (v < 0) throw wrong(whole);
    out[out.length - (n - whole === 3 ? 2 : 1)] = v >>> 16;
    if (n - whole === 3) out[out.length - 1] = v >>> 8 & 255;
  }
  return out;
}

async function pipe(bytes, stream) {
  return new Uint8Array(await new Response(new Blob([bytes]).stream().pipeThrough(stream)).arrayBuffer());
}

/** The `edits` parameter: positions - original as float32, deflated. */
export async function encodeEdits(positions, original) {
  const delta = new Float32Array(positions.length);
  for (let i = 0; i < positions.length; i++) delta[i] = positions[i] - original[i];
  return toBase64Url(await pipe(new Uint8Array(delta.buffer), new CompressionStream('deflate-raw')));
}

/** Positions from an `edits` parameter over the original ones; throws a sentence when it does not fit. */
export async function decodeEdits(text, original) {
  let bytes;
  try {
    bytes = await pipe(fromBase64Url(text), new DecompressionStream('deflate-raw'));
  } catch {
    throw new Error('the link\'s edits are damaged (not valid compressed data)');
  }
  if (bytes.byteLength !== 4 * original.length)
    throw new Error(`the link's edits are for a model with ${bytes.byteLength / 12} vertices, this one has ${original.length / 3}`);
  const delta = new Float32Array(bytes.buffer, 0, original.length);
  return Float64Array.from(original, (x, i) => x + delta[i]);
}

/** The share link of a sample with its edits and settings. */
export async function shareUrl({ name, positions, original, reference, settings }) {
  const url = new URL(location.href);
  url.search = '';
  url.hash = '';
  url.searchParams.set('model', name);
  url.searchParams.set('level', String(settings.level));
  url.searchParams.set('scheme', settings.scheme);
  if (!settings.preserve) url.searchParams.set('preserve', '0');
  if (settings.keepBalance) url.searchParams.set('balance', '1');
  if (settings.surface === 'limit') url.searchParams.set('surface', 'limit');
  url.searchParams.set('reference', String(reference));
  url.searchParams.set('edits', await encodeEdits(positions, original));
  return url.href;
}

/** The parameters a share link sets besides `model` (dropped once applied). */
export const SHARE_PARAMS = Object.freeze(['edits', 'level', 'scheme', 'preserve', 'balance', 'surface', 'reference']);

/** The shared state in a URL's parameters, or null: { name, level, scheme, preserve, keepBalance, surface, reference, edits }. */
export function sharedState(params) {
  const edits = params.get('edits'), name = params.get('model');
  if (!edits || !name) return null;
  const level = Number(params.get('level') ?? 0), reference = Number(params.get('reference'));
  return {
    name, edits, level: Number.isInteger(level) && level >= 0 ? level : 0, scheme: params.get('scheme') ?? undefined,
    preserve: params.get('preserve') !== '0', keepBalance: params.get('balance') === '1',
    surface: params.get('surface') === 'limit' ? 'limit' : 'mesh', reference: Number.isFinite(reference) ? reference : null,
  };
}

/**
 * A project file (JSON, as a Blob): the model's OBJ text, or its file's bytes in base64url with its
 * format, the edited positions (float64, base64url), the reference volume and the settings. Made of
 * parts: the big strings never exist as JS strings.
 */
export function projectBlob({ model, positions, reference, settings }) {
  const head = JSON.stringify({ format: PROJECT_FORMAT, version: PROJECT_VERSION, reference, settings });
  const { name, kind, text, bytes, format } = model;
  const modelHead = `${head.slice(0, -1)},"model":{"name":${JSON.stringify(name)},"kind":${JSON.stringify(kind)}`;
  const modelParts = typeof text === 'string' ? [`,"text":${JSON.stringify(text)}}`]
    : [`,"format":${JSON.stringify(format ?? '')},"bytes":"`, base64UrlBytes(bytes), '"}'];
  const positionBytes = new Uint8Array(positions.buffer, positions.byteOffset, positions.byteLength);
  return new Blob([modelHead, ...modelParts, ',"positions":"', base64UrlBytes(positionBytes), '"}'], { type: 'application/json' });
}

/** Whether a file's text looks like a project (JSON) rather than an OBJ. */
export function isProject(text) {
  return /^\s*\{/.test(text);
}

/** Reads a project file: { model: { name, kind, text }, positions, reference, settings }; throws a sentence naming what is wrong. */
export function readProject(text, fileName) {
  let data;
  try {
    data = JSON.parse(text);
  } catch (e) {
    throw new Error(`${fileName} is not a project file: ${e.message}`, { cause: e });
  }
  if (data?.format !== PROJECT_FORMAT) throw new Error(`${fileName} is not an mrvol project (its "format" is ${JSON.stringify(data?.format)})`);
  if (data.version !== PROJECT_VERSION) throw new Error(`${fileName} is a version ${data.version} project; this editor reads version ${PROJECT_VERSION}`);
  if ((typeof data.model?.text !== 'string' && typeof data.model?.bytes !== 'string') || typeof data.model?.name !== 'string')
    throw new Error(`${fileName}: the project has no model (model.name and model.text)`);
  let positions = null;
  if (typeof data.positions === 'string') {
    const bytes = fromBase64Url(data.positions, `${fileName}: "positions"`);
    if (bytes.byteLength % 8 !== 0) throw new Error(`${fileName}: "positions" is not a list of float64 numbers`);
    positions = new Float64Array(bytes.buffer, 0, bytes.byteLength / 8);
  }
  const model = typeof data.model.text === 'string' ? { name: data.model.name, kind: 'file', text: data.model.text }
    : { name: data.model.name, kind: 'file', bytes: fromBase64Url(data.model.bytes, `${fileName}: "model.bytes"`), format: String(data.model.format ?? '') };
  return { model, positions, reference: data.reference ?? null, settings: data.settings ?? {} };
}
