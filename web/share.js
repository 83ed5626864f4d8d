// Sharing an edited model: a link (a sample's name, the settings and the edit as the difference of
// the fine positions from the sample's own, float32, deflated, base64url, in `?edits=`) and a
// project file (JSON: the model's OBJ text, the edited positions, the reference volume, the
// settings). Both restore the shape through the same path as a stored session.

const PROJECT_FORMAT = 'mrvol-project';
const PROJECT_VERSION = 1;

function toBase64Url(bytes) {
  let binary = '';
  for (let i = 0; i < bytes.length; i += 0x8000) binary += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(binary).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
}

function fromBase64Url(text) {
  const binary = atob(text.replace(/-/g, '+').replace(/_/g, '/'));
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  return bytes;
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

/** A project file's text. */
export function projectText({ model, positions, reference, settings }) {
  const bytes = new Uint8Array(positions.buffer, positions.byteOffset, positions.byteLength);
  return JSON.stringify({
    format: PROJECT_FORMAT, version: PROJECT_VERSION, model: projectModel(model),
    positions: toBase64Url(bytes), reference, settings,
  });
}

// The model in a project: an OBJ as its text; another format's file as base64url bytes with its format.
function projectModel({ name, kind, text, bytes, format }) {
  if (typeof text === 'string') return { name, kind, text };
  if (format === 'obj') return { name, kind, text: new TextDecoder().decode(bytes) };
  return { name, kind, format, bytes: toBase64Url(bytes) };
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
    const bytes = fromBase64Url(data.positions);
    if (bytes.byteLength % 8 !== 0) throw new Error(`${fileName}: "positions" is not a list of float64 numbers`);
    positions = new Float64Array(bytes.buffer, 0, bytes.byteLength / 8);
  }
  const model = typeof data.model.text === 'string' ? { name: data.model.name, kind: 'file', text: data.model.text }
    : { name: data.model.name, kind: 'file', bytes: fromBase64Url(data.model.bytes), format: String(data.model.format ?? '') };
  return { model, positions, reference: data.reference ?? null, settings: data.settings ?? {} };
}
