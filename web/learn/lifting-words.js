// The lifting view's words for each scheme: the title, the paragraph on what one synthesis level
// does, a glossary line per phase (the core's step names; method.md sections 2-4 and
// docs/catmull-clark.md for the exact masks), and the names of the two kinds of vertex the
// "next" buttons pick. The view shows the words of the scheme it plays, nothing of the others.

const LOOP = {
  title: 'Lifting: one Loop level, phase by phase (Figure 3, section 2)',
  intro: 'One synthesis step (c<sup>l−1</sup>, d<sup>l−1</sup>) → c<sup>l</sup> of the Loop-based scheme runs four phases in place ' +
    '(section 2, Figure 3): <b>U</b> updates the even (old) vertices from the details of the odd (new) ones ' +
    '(weights α/v, β/v), <b>P<sub>o</sub></b> predicts the odd vertices from the even ones (3/8, 3/8, 1/8, 1/8), ' +
    '<b>N</b> scales the even vertices by 8/5 (3/8 + cos(2π/v)/4)², <b>P<sub>e</sub></b> moves the even vertices by μ times ' +
    'their odd neighbours. With zero details this is Loop subdivision.',
  phases: {
    U: 'update: each even vertex reads the details d of its odd neighbours (α/v on its edges, β/v on its link)',
    P_o: 'predict odd: each odd vertex reads the ends and wings of its edge (3/8, 3/8, 1/8, 1/8)',
    N: 'normalize: each even vertex is scaled by K = 8/5 (3/8 + cos(2π/v)/4)²',
    P_e: 'predict even: each even vertex reads its odd neighbours (μ = (1 − K)/v each)',
  },
  even: 'even', odd: 'odd',
};

const BUTTERFLY = {
  title: 'Lifting: one Butterfly level, phase by phase (section 2)',
  intro: 'One synthesis step (c<sup>l−1</sup>, d<sup>l−1</sup>) → c<sup>l</sup> of the Butterfly-based scheme (interpolating, ' +
    'lifted as Schröder and Sweldens\' spherical wavelets) runs two phases in place: <b>U</b> updates the even (old) vertices ' +
    'from the details of the odd (new) vertices on their edges (weights −I<sub>m</sub>/(2I<sub>k</sub>), the integrals I of the ' +
    'basis functions, so that each wavelet integrates to zero; −1/8 where the mesh is regular), <b>P</b> predicts the odd ' +
    'vertices with the modified Butterfly mask (1/2 on the edge\'s ends, 1/8 on its wings, −1/16 on the four vertices beyond; ' +
    'at an extraordinary end its 1-ring stencil, 3/4 on the end). With zero details this is Butterfly subdivision: the even ' +
    'vertices stay where they are.',
  phases: {
    U: 'update: each even vertex reads the details d of the odd vertices on its edges (−I_m/(2 I_k) each, −1/8 when regular)',
    P: 'predict: each odd vertex reads the Butterfly mask of its edge (1/2 on the ends, 1/8 on the wings, −1/16 beyond)',
  },
  even: 'even', odd: 'odd',
};

const LINEAR = {
  title: 'Lifting: one linear level, phase by phase (section 2)',
  intro: 'One synthesis step (c<sup>l−1</sup>, d<sup>l−1</sup>) → c<sup>l</sup> of the linear (Lounsbery) scheme, lifted, runs two ' +
    'phases in place: <b>U</b> updates each even (old) vertex of valence n from the details of the n odd (new) vertices on its ' +
    'edges (−3/(4n) each), <b>P</b> predicts each odd vertex as the midpoint of its edge (1/2, 1/2). With zero details this ' +
    'is the 1-to-4 split of the flat triangles.',
  phases: {
    U: 'update: each even vertex of valence n reads the details d on its n edges (−3/(4n) each)',
    P: 'predict: each odd vertex reads the two ends of its edge (1/2 each)',
  },
  even: 'even', odd: 'odd',
};

const CATMULL_CLARK = {
  title: 'Lifting: one Catmull-Clark level, phase by phase (docs/catmull-clark.md)',
  intro: 'One synthesis step (c<sup>l−1</sup>, d<sup>l−1</sup>) → c<sup>l</sup> of the lifted Catmull-Clark scheme runs, in place, ' +
    '<b>P<sub>f</sub></b> (face points: the mean of the quad\'s corners), <b>P<sub>e</sub></b> (edge points: the edge\'s ends and ' +
    'the face points beside it, 1/4 each), then the old vertices: <b>N<sub>v</sub></b> scales each by (n − 3)/n and ' +
    '<b>P<sub>v</sub></b> adds 4/n² of its edge points and −1/n² of its face points, which is Catmull-Clark\'s vertex rule ' +
    '(Q + 2R + (n − 3)v)/n rewritten with the new points. At a valence-3 vertex (n − 3)/n is 0, so it gets its own steps ' +
    '<b>N<sub>3k</sub></b>, <b>P<sub>3k</sub></b> first. The new points (face and edge points) are odd, the old vertices even; ' +
    'with zero details this is Catmull-Clark subdivision.',
  phases: {
    P_f: 'face points: each face point reads the four corners of its quad (1/4 each)',
    P_e: 'edge points: each edge point reads its two ends and the two face points beside it (1/4 each; on a boundary its ends, 1/2 each)',
    N_3k: 'valence-3 layer, normalize: an old vertex of valence 3 is scaled by 1/9 (the vertex rule alone would forget it)',
    P_3k: 'valence-3 layer, predict: it reads its edge points, face points and the coarse neighbours of the layer before',
    N_v: 'normalize old vertices: each old vertex of valence n is scaled by (n − 3)/n (boundary: 1/2)',
    P_v: 'vertex rule: each old vertex reads its n edge points (4/n² each) and its face points (−1/n² each)',
  },
  even: 'old vertex', odd: 'new point',
};

export const SCHEME_WORDS = { loop: LOOP, butterfly: BUTTERFLY, linear: LINEAR, 'catmull-clark': CATMULL_CLARK };

// The valence-3 layers' steps are numbered by layer (N_31, P_31, ...); the glossary has one line for them.
const glossaryKey = (name) => name.replace(/^([NP])_3\d+$/, '$1_3k');

/** What the step `name` of `scheme` does (its glossary line), or the name itself if unknown. */
export function phaseText(scheme, name) {
  return SCHEME_WORDS[scheme]?.phases[glossaryKey(name)] ?? name;
}

/** The glossary keys of the steps `names` (in order, once each): the lines the glossary shows. */
export function glossaryKeys(names) {
  return [...new Set(names.map(glossaryKey))];
}

/** A glossary key as HTML: P_o → P<sub>o</sub>, N_3k → N<sub>3k</sub>. */
export function phaseLabel(key) {
  const [head, tail] = key.split('_');
  return tail ? `${head}<sub>${tail}</sub>` : head;
}
