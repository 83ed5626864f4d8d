// What the triangle editor (lib/api.mjs VolumeEditor) and the quad editor (lib/quad.mjs
// QuadVolumeEditor) make of their arguments alike, so that one caller can drive either.

/**
 * A drag as a cage target: moves = [{ vertex, position: [x, y, z] } | { vertex, offset: [dx, dy, dz] }]
 * with caller vertex indices; those vertices are held. Returns { target, held } for deformCage
 * (target: the editor's drag buffer when it keeps one, rewritten by the next call).
 */
export function cageTargetOf(editor, moves) {
  const target = editor._dragTarget ? editor._dragTarget() : editor.cagePositions();
  const held = new Uint8Array(editor.cageSize);
  for (const move of moves) {
    const c = editor.cageIndexOf(move.vertex);
    const to = move.position ?? [0, 1, 2].map((k) => target[3 * c + k] + (move.offset?.[k] ?? 0));
    for (let k = 0; k < 3; k++) target[3 * c + k] = to[k];
    held[c] = 1;
  }
  return { target, held };
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
