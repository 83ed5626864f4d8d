// Tooltips of the teaching views' controls (issue 13: "a tooltip on every control"), by data-testid,
// given after a view is mounted to every control without one (titleControls), and of the nav links.
const TITLES = {
  'levels-model': 'The mesh shown: a sample, or the editor\'s model with its edits',
  'levels-scheme': 'The wavelet scheme of the analysis and synthesis (Loop, butterfly or linear)',
  'levels-compare': 'Show the three schemes side by side at the same level',
  'levels-level': 'Level l: the surface with every detail of level l and finer set to zero',
  'levels-details': 'How the details dropped are drawn: arrows, a colour map of their size, or not at all',
  'levels-ghosts': 'Draw the coarser levels faintly behind the current one',
  'levels-play-analysis': 'Play the analysis: from the fine mesh down to level 0, one level at a time',
  'levels-play-synthesis': 'Play the synthesis: from level 0 back up to the fine mesh',
  'levels-wavelet': 'Set one detail coefficient to 1 and every other to 0: its wavelet (basis function) appears on the mesh',
  'levels-wavelet-next': 'Show the next detail coefficient\'s wavelet',
  'ball-squash': 'How far the floor squashes the ball, as a share of its height',
  'demo-play': 'Pause or play the animation',
  'demo-restart': 'Start the animation again from the beginning',
  'tensor-mesh': 'The small mesh whose tensors θˡ are computed and drawn',
  'tensor-scheme': 'The wavelet scheme whose transposed filters make θˡ from the fine θⁿ',
  'tensor-orderings': 'Draw every ordering of (i, j, k) (the tensor is alternating); off: only the stored i < j < k',
  'tensor-outwards-link': 'The lifting view, where the transposed masks play phase by phase',
  'bunny-level': 'Level e of the cage whose control vertices are dragged',
  'bunny-pull': 'How far the ears are pulled',
  'balance-pull': 'How far the ears are pulled',
  'lifting-model': 'The mesh whose level is played',
  'lifting-level': 'The level step played: from Mˡ⁻¹ to Mˡ',
  'lifting-scheme': 'The scheme whose lifting phases are played',
  'lifting-mode': 'Synthesis (the phases in order), analysis (their inverses in reverse order) or the transposed masks (how θ is made)',
  'lifting-vertex': 'The picked vertex (its index at level l); clicking the mesh picks one too',
  'lifting-next-even': 'Pick the next even (old) vertex',
  'lifting-next-odd': 'Pick the next odd (new) vertex',
  'lifting-step': 'Run the next phase',
  'lifting-play': 'Play every phase in turn',
  'lifting-reset': 'Back to before the first phase',
};
// Families of controls made per level.
const PREFIXED = [['bank-', (id) => `Go to level ${id.slice(5)}: the coarse shape c at that level, the finer details d set aside`]];

/** What each nav link opens. */
export const NAV_TITLES = {
  'learn/levels': 'Analysis and synthesis: a mesh level by level, its details and its wavelets',
  'demo/ball': 'A bouncing ball squashed by the floor, with and without volume preservation (Figure 6)',
  'demo/skinning': 'A skeleton bends a tube: skinning loses volume, the correction keeps it',
  'learn/tensor': 'The volume tensors θˡ, block by block and entry by entry (Figure 4)',
  'demo/bunny': 'Pulling the bunny\'s ears: the free part grows, the preserved part keeps its volume',
  'demo/balance': 'Keeping the centre of mass where it is, with the volume',
  'learn/lifting': 'One level of the lifting scheme, phase by phase (Figure 3)',
};

/** Gives every control under `root` without a tooltip its title (by data-testid). */
export function titleControls(root) {
  for (const control of root.querySelectorAll('button, input, select, a[href]')) {
    if (control.closest('[title]')?.title?.trim()) continue;
    const id = control.dataset.testid ?? '';
    const title = TITLES[id] ?? PREFIXED.find(([prefix]) => id.startsWith(prefix))?.[1](id);
    if (title) control.title = title;
  }
}
