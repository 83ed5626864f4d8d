// What the triangle editor (lib/api.mjs VolumeEditor) and the quad editor (lib/quad.mjs
// QuadVolumeEditor) make of their arguments alike, so that one caller can drive either.

/** The largest coordinate a mesh may have (the readers' limit): its volume's cubes stay finite. */
const COORDINATE_LIMIT = 1e100;

/**
 * A drag as a cage target: moves = [{ vertex, position: [x, y, z] } | { vertex, offset: [dx, dy, dz] }]
 * with caller vertex indices; those vertices are held. Returns { target, held } for deformCage
 * (target: the editor's drag buffer when it keeps one, rewritten by the next call). A move that is
 * not one of those two forms, or that puts a vertex beyond the coordinates a mesh may have, throws
 * MrvolError naming it.
 */
export function cageTargetOf(editor, moves, MrvolError) {
  if (!Array.isArray(moves)) throw new MrvolError('moves must be an array of { vertex, position: [x, y, z] } or { vertex, offset: [dx, dy, dz] }');
  const target = editor._dragTarget ? editor._dragTarget() : editor.cagePositions();
  const held = new Uint8Array(editor.cageSize);
  for (let m = 0; m < moves.length; m++) {
    const move = moves[m];
    const what = `moves[${m}]`;
    if (!move || typeof move !== 'object') throw new MrvolError(`${what} must be { vertex, position: [x, y, z] } or { vertex, offset: [dx, dy, dz] }`);
    const hasPosition = move.position !== undefined, hasOffset = move.offset !== undefined;
    if (hasPosition === hasOffset)
      throw new MrvolError(`${what} must give either position: [x, y, z] or offset: [dx, dy, dz]${hasPosition ? ', not both' : ''}`);
    const given = hasPosition ? move.position : move.offset, name = hasPosition ? 'position' : 'offset';
    if (!(Array.isArray(given) || ArrayBuffer.isView(given)) || given.length !== 3 || ![0, 1, 2].every((k) => typeof given[k] === 'number' && Number.isFinite(given[k])))
      throw new MrvolError(`${what}.${name} must be 3 finite numbers, got ${describe(given)}`);
    const c = editor.cageIndexOf(move.vertex);
    for (let k = 0; k < 3; k++) {
      const to = hasPosition ? given[k] : target[3 * c + k] + given[k];
      if (Math.abs(to) > COORDINATE_LIMIT)
        throw new MrvolError(`${what} puts vertex ${move.vertex} at ${'xyz'[k]} = ${to}: coordinates must stay within +-${COORDINATE_LIMIT}`);
      target[3 * c + k] = to;
    }
    held[c] = 1;
  }
  return { target, held };
}

/** A short description of a value for an error message. */
function describe(value) {
  if (Array.isArray(value) || ArrayBuffer.isView(value)) return `[${Array.from(value).slice(0, 4).map(String).join(', ')}${value.length > 4 ? ', ...' : ''}] (${value.length} values)`;
  return value === null ? 'null' : typeof value === 'object' ? 'an object' : String(value);
}

/**
 * deformCage's target within the coordinates a mesh may have (beyond them a drag made a shape of
 * infinite or NaN volume, written to a file no reader takes back). Its length and the non-finite
 * numbers the core checks. Throws MrvolError naming the first coordinate out of range.
 */
export function checkCageTarget(target, MrvolError) {
  if (!(target instanceof Float64Array)) throw new MrvolError('target must be a Float64Array');
  for (let i = 0; i < target.length; i++)
    if (Math.abs(target[i]) > COORDINATE_LIMIT)
      throw new MrvolError(`target: cage vertex ${(i / 3) | 0} has ${'xyz'[i % 3]} = ${target[i]}: coordinates must stay within +-${COORDINATE_LIMIT}`);
}

// What an editor keeps: the volume, and optionally the centre of mass ('centroid').
const KEEPABLE = ['volume', 'centroid'];

/** createEditor's `keep` (a list, or a comma-separated string) checked: the list. */
export function keepListOf(keep, MrvolError) {
  const list = typeof keep === 'string' ? keep.split(',').map((k) => k.trim()) : (keep ?? ['volume']);
  if (!Array.isArray(list)) throw new MrvolError(`keep must be a list such as ['volume', 'centroid'], got ${JSON.stringify(keep)}`);
  for (const k of list)
    if (!KEEPABLE.includes(k))
      throw new MrvolError(`keep: unknown quantity ${JSON.stringify(k)} (volume, centroid${k === 'inertia' ? '; the inertia tensor is not kept yet' : ''})`);
  if (!list.includes('volume')) throw new MrvolError('keep must include volume (the centre of mass is kept with it)');
  return list;
}

const FREE_MODES = { 'minus-held': 'minus-held', cage: 'minus-held', all: 'all' };

/**
 * setFreeSet's raw arguments [mode, list (cage order) or undefined, detail levels]: cage
 * 'minus-held' (or 'cage'), 'all', or a list of caller vertex indices.
 */
export function freeSetArgs(editor, { cage = 'minus-held', detailLevels = [] }, { MrvolError, levelArg }) {
  const levels = Int32Array.from(detailLevels, (l) => levelArg(l, 'detail level'));
  if (typeof cage !== 'string') return ['list', Uint32Array.from(cage, (v) => editor.cageIndexOf(v)), levels];
  if (!FREE_MODES[cage]) throw new MrvolError(`unknown free set '${cage}' (minus-held, all or a list of vertices)`);
  return [FREE_MODES[cage], undefined, levels];
}
