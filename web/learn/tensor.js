// #learn/tensor: the block structure of the volume tensors theta^l, l = n .. e (Figure 4, paper
// section 3.1), from live tensors: computeTheta({ level: l, storage: 'full' }) for every l, its
// stored entries from theta.entries(). Indices are in hierarchy order, grouped by depth
// (mr.hierarchyOrder() maps them to vertices); an entry's colour says how many of its three
// indices are coarse at level l.
import { Stage, THREE, surface, wire, edgesOf, bounds, explain, control, select, readoutTable } from './stage.js';

const HIGHLIGHT = [0xe36209, 0x1f6feb, 0x8250df]; // i, j, k

const CLASS_COLORS = ['#2da44e', '#d4a72c', '#54aeff', '#0b3d91']; // 0, 1, 2, 3 coarse indices
const CLASS_NAMES = ['no coarse index (details only)', '1 coarse', '2 coarse', '3 coarse'];

const OCTAHEDRON = {
  positions: Float64Array.from([1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1]),
  faces: Uint32Array.from([0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5]),
};
const TETRAHEDRON = {
  positions: Float64Array.from([1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1]),
  faces: Uint32Array.from([0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2]),
};

export async function mount({ mrvol, layout, el }) {
  explain(layout.text, 'The volume tensors θˡ (Figure 4, section 3.1)', [
    'At the fine level the volume is a trilinear form Θ = Σ θ<sup>n</sup><sub>ijk</sub> x<sub>i</sub> y<sub>j</sub> z<sub>k</sub>: ' +
      'θ<sup>n</sup><sub>ijk</sub> = ±1/6 when ijk is a triangle. Since synthesis is linear, the volume is also a trilinear ' +
      'form of the level-l coefficients; θ<sup>l−1</sup> comes from θ<sup>l</sup> by applying the transposed synthesis ' +
      'filters (S<sup>l</sup>)<sup>T</sup>, (C<sup>l</sup>)<sup>T</sup> along each of the three axes (section 3.1, Figure 4). ' +
      'Those transposed filters are the lifting masks applied <i>outwards</i>, in reverse order (section 3.2, Figure 5): ' +
      'watch them phase by phase in <a href="#learn/lifting" data-testid="tensor-outwards-link">the lifting view</a>, direction “transposed”.',
    'Each row of pictures is one live tensor θ<sup>l</sup> of the small mesh beside them, computed by the core with every entry kept. ' +
      'Indices are sorted by depth (the level where a vertex is born; grey lines separate the groups). One picture per group of ' +
      'the third index k shows which (i, j) have a non-zero θ<sub>ijk</sub> (all orderings), coloured by how many of ' +
      'i, j, k are <b>coarse</b> (depth ≤ l) — the rest are details.',
    'From θ<sup>n</sup> to θ<sup>e</sup> the tensor fills in (section 3.2). It is alternating, so only i &lt; j &lt; k is ' +
      'stored; and when only coarse vertices move (the free set F of section 4), the green entries (no coarse index) ' +
      'are a constant and need not be stored at all.',
    '<b>Point at a picture</b> (touch it, or Tab to it and use the arrow keys): the entry under the pointer, θ<sub>ijk</sub> with the largest |value| among ' +
      'the k of that picture, is read out and its three vertices light up on the mesh (i orange, j blue, k purple). ' +
      'At the fine level every entry is a triangle of the mesh, ±1/6; coarser, the masks spread each one over a patch.',
  ]);
  const meshes = {
    'octahedron, n = 2': () => mrvol.subdivide(OCTAHEDRON, { levels: 2 }),
    'tetrahedron, n = 3': () => mrvol.subdivide(TETRAHEDRON, { levels: 3 }),
    'icosahedron, n = 2': async () => {
      const text = await (await fetch(`${import.meta.env.BASE_URL}models/icosahedron.obj`)).text();
      return mrvol.subdivide(mrvol.readObj(text), { levels: 2 });
    },
  };
  const s = { mesh: 'octahedron, n = 2', scheme: 'loop', allOrderings: true };
  const meshSelect = control(layout.controls, 'mesh', select(Object.keys(meshes).map((k) => [k, k]), s.mesh, 'tensor-mesh'));
  const schemeSelect = control(layout.controls, 'scheme', select(['loop', 'butterfly', 'linear'].map((k) => [k, k]), s.scheme, 'tensor-scheme'));
  const legend = el('div', { class: 'learn-legend' });
  CLASS_COLORS.forEach((c, i) => {
    const item = el('span', {}, el('i', { style: `background:${c}` }), CLASS_NAMES[i]);
    legend.append(item);
  });
  layout.controls.append(legend);
  const set = readoutTable(layout.readouts, [['mesh', 'tensor-info'], ['computed in', 'tensor-ms']]);
  const tableBox = el('div', { testid: 'tensor-blocks' });
  layout.readouts.append(tableBox);
  const grid = el('div', { class: 'tensor-grid', testid: 'tensor-grid' });
  const meshView = el('div', { class: 'tensor-mesh-view', testid: 'tensor-mesh' });
  const hoverBox = el('div', { class: 'tensor-hover', testid: 'tensor-hover', text: 'Point at a picture: its entry’s vertices light up here.' });
  layout.stage.append(el('div', { class: 'tensor-layout' }, el('div', { class: 'tensor-mesh' }, meshView, hoverBox), grid));
  const meshStage = new Stage(meshView, ['']);
  // A ring on the picture under the pointer, around the cell (i, j) read out.
  const cursor = el('div', { class: 'tensor-cursor', testid: 'tensor-cursor' });
  let result = null;
  let shown = null; // { mr-free copy: positions, faces, order (hierarchy index -> vertex), lookup per level, groupStart, N, markers }
  let hover = null;

  /** The small mesh: surface, edges, and three markers for the hovered entry's vertices. */
  function showMesh(positions, faces) {
    const scene = meshStage.panels[0].scene;
    scene.traverse((o) => o.geometry?.dispose());
    scene.children.filter((o) => !o.isLight).forEach((o) => scene.remove(o));
    scene.add(surface(positions, faces, { color: 0xe8e2d8 }));
    scene.add(wire(positions, edgesOf(faces), { color: 0x8c959f, points: false }));
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(9), 3));
    const colors = new Float32Array(9);
    HIGHLIGHT.forEach((c, m) => new THREE.Color(c).toArray(colors, 3 * m));
    geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    geometry.setDrawRange(0, 0);
    const markers = new THREE.Points(geometry, new THREE.PointsMaterial({ size: 16, sizeAttenuation: false, vertexColors: true, depthTest: false }));
    markers.renderOrder = 3;
    markers.frustumCulled = false;
    scene.add(markers);
    const b = bounds(positions);
    meshStage.frame(b.center, b.radius);
    return markers;
  }

  const SIGN = (a, b, c) => { // sign of the permutation sorting (a, b, c), all distinct
    let s = 1;
    if (a > b) s = -s;
    if (a > c) s = -s;
    if (b > c) s = -s;
    return s;
  };

  /** The entry under (a, b) in the picture of level l and k-group g: the k of that group with the largest |theta_abk|. */
  function entryAt(l, g, a, b) {
    const { lookup, groupStart, N } = shown;
    const values = lookup.get(l);
    let best = null, count = 0;
    if (a === b) return { best, count };
    for (let k = groupStart[g]; k < groupStart[g + 1]; k++) {
      if (k === a || k === b) continue;
      const [x, y, z] = [a, b, k].sort((p, q) => p - q);
      const stored = values.get((x * N + y) * N + z);
      if (!stored) continue;
      count++;
      const value = SIGN(a, b, k) * stored;
      if (!best || Math.abs(value) > Math.abs(best.value)) best = { i: a, j: b, k, value };
    }
    return { best, count };
  }

  function hoverAt(l, g, a, b) {
    const { best, count } = entryAt(l, g, a, b);
    const { order, positions } = shown;
    const attribute = shown.markers.geometry.getAttribute('position');
    if (!best) {
      hover = { level: l, group: g, i: a, j: b, k: null, value: 0, vertices: [] };
      shown.markers.geometry.setDrawRange(0, 0);
      hoverBox.textContent = `θ${sup(l)}: no non-zero entry at i = ${a}, j = ${b} for k in this picture`;
    } else {
      const vertices = [best.i, best.j, best.k].map((h) => order[h]);
      vertices.forEach((v, m) => attribute.setXYZ(m, positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]));
      attribute.needsUpdate = true;
      shown.markers.geometry.setDrawRange(0, 3);
      hover = { level: l, group: g, ...best, vertices, others: count - 1 };
      hoverBox.replaceChildren(
        el('div', { text: `θ${sup(l)}[${best.i}, ${best.j}, ${best.k}] = ${best.value.toPrecision(4)}` }),
        el('div', { text: `vertices ${vertices.join(', ')}${count > 1 ? ` · ${count - 1} more k here` : ''}` }));
    }
    hoverBox.dataset.value = hover.value;
    meshStage.requestRender();
  }

  async function build() {
    const mr = await meshes[s.mesh]();
    try {
      const order = mr.hierarchyOrder();
      const positions = mr.positions(), faces = mr.faces();
      shown = { order, positions, faces, lookup: new Map(), N: order.length, markers: showMesh(positions, faces) };
      hover = null;
      const n = mr.levels;
      const depths = mr.depths();
      const depthOf = Uint8Array.from(mr.hierarchyOrder(), (v) => depths[v]); // hierarchy order: by depth
      const N = depthOf.length;
      const groupStart = [];
      for (let g = 0; g <= n; g++) groupStart.push(depthOf.indexOf(g));
      groupStart.push(N);
      shown.groupStart = groupStart;
      grid.replaceChildren();
      tableBox.replaceChildren();
      // The tensors take a second or more on a bigger mesh: said first, and painted before the work.
      layout.status.textContent = `Computing θ at ${n + 1} levels for ${s.mesh} (${s.scheme}) …`;
      set('tensor-ms', 'computing …');
      await new Promise((resolve) => requestAnimationFrame(() => setTimeout(resolve)));
      const started = performance.now();
      const levels = [];
      for (let l = n; l >= 0; l--) {
        const theta = mr.computeTheta({ level: l, storage: 'full', scheme: s.scheme });
        const info = theta.info();
        const entries = theta.entries();
        theta.delete();
        const values = new Map();
        for (let t = 0; t < entries.values.length; t++)
          if (entries.values[t] !== 0) values.set((entries.i[t] * N + entries.j[t]) * N + entries.k[t], entries.values[t]);
        shown.lookup.set(l, values);
        levels.push(draw(l, entries, info, depthOf, groupStart, n));
      }
      result = { n, N, levels, ms: performance.now() - started };
      set('tensor-info', `${s.mesh}: N = ${N}, levels ${n} → 0, ${s.scheme}`);
      set('tensor-ms', `${result.ms.toFixed(0)} ms for ${n + 1} tensors`, result.ms);
    } finally {
      layout.status.textContent = '';
      mr.delete();
    }
  }

  function draw(l, entries, info, depth, groupStart, n) {
    const N = info.vertices;
    const groups = n + 1;
    const pixels = Array.from({ length: groups }, () => new Uint32Array(N * N)); // count per (slab, i, j)
    const classCounts = [0, 0, 0, 0];
    const blockCounts = new Map(); // "ga,gb,gc" (sorted groups) -> stored entries
    const coarse = (v) => (depth[v] <= l ? 1 : 0);
    for (let t = 0; t < entries.values.length; t++) {
      if (entries.values[t] === 0) continue;
      const i = entries.i[t], j = entries.j[t], k = entries.k[t];
      classCounts[coarse(i) + coarse(j) + coarse(k)]++;
      const key = [depth[i], depth[j], depth[k]].join(',');
      blockCounts.set(key, (blockCounts.get(key) ?? 0) + 1);
      // every ordering: the third index picks the slab, the other two the pixel
      for (const [a, b, c] of [[i, j, k], [j, i, k], [i, k, j], [k, i, j], [j, k, i], [k, j, i]]) {
        if (!s.allOrderings && !(a < b && b < c)) continue;
        pixels[depth[c]][a * N + b]++;
      }
    }
    const scale = Math.max(1, Math.floor(200 / N));
    const row = el('div', { class: 'tensor-level', testid: `tensor-level-${l}` });
    const stored = classCounts.reduce((x, y) => x + y, 0);
    row.append(el('h3', { text: `θ${sup(l)}: coarse = depth ≤ ${l} · ${stored} stored entries (i<j<k), ${info.nnzFull ?? '?'} non-zeros in all` }));
    const slabs = el('div', { class: 'tensor-slabs' });
    for (let g = 0; g < groups; g++) {
      const canvas = document.createElement('canvas');
      canvas.width = canvas.height = N * scale;
      canvas.dataset.testid = `tensor-slab-${l}-${g}`;
      let cell = [0, 0]; // (i, j) read out: by the pointer, or the arrow keys once the picture has focus
      const pointAt = (a, b) => {
        if (a < 0 || a >= N || b < 0 || b >= N) return;
        cell = [a, b];
        const rect = canvas.getBoundingClientRect();
        canvas.parentElement.append(cursor);
        Object.assign(cursor.style, { left: `${canvas.offsetLeft + (b + 0.5) * rect.width / N}px`, top: `${canvas.offsetTop + (a + 0.5) * rect.height / N}px` });
        hoverAt(l, g, a, b);
      };
      const at = (e) => {
        const rect = canvas.getBoundingClientRect();
        pointAt(Math.floor((e.clientY - rect.top) / rect.height * N), Math.floor((e.clientX - rect.left) / rect.width * N));
      };
      canvas.addEventListener('pointermove', at);
      canvas.addEventListener('pointerdown', at);
      // The keyboard's way in: Tab to a picture, the arrows move the read-out cell (Home: the first).
      canvas.tabIndex = 0;
      canvas.setAttribute('role', 'img');
      canvas.setAttribute('aria-label', `θ${sup(l)} slab ${g}: arrow keys read out its entries`);
      canvas.addEventListener('focus', () => pointAt(...cell));
      canvas.addEventListener('keydown', (e) => {
        const step = { ArrowUp: [-1, 0], ArrowDown: [1, 0], ArrowLeft: [0, -1], ArrowRight: [0, 1] }[e.key];
        if (e.key === 'Home') pointAt(0, 0);
        else if (step) pointAt(Math.min(N - 1, Math.max(0, cell[0] + step[0])), Math.min(N - 1, Math.max(0, cell[1] + step[1])));
        else return;
        e.preventDefault();
      });
      const ctx = canvas.getContext('2d');
      ctx.fillStyle = '#ffffff';
      ctx.fillRect(0, 0, N * scale, N * scale);
      let max = 1;
      for (const c of pixels[g]) max = Math.max(max, c);
      for (let a = 0; a < N; a++)
        for (let b = 0; b < N; b++) {
          const count = pixels[g][a * N + b];
          if (!count) continue;
          ctx.globalAlpha = 0.35 + 0.65 * Math.log1p(count) / Math.log1p(max);
          ctx.fillStyle = CLASS_COLORS[coarse(a) + coarse(b) + (g <= l ? 1 : 0)];
          ctx.fillRect(b * scale, a * scale, scale, scale);
        }
      ctx.globalAlpha = 1;
      ctx.strokeStyle = '#8c959f';
      ctx.lineWidth = 1;
      for (const x of groupStart.slice(1, -1)) {
        ctx.beginPath();
        ctx.moveTo(x * scale + 0.5, 0); ctx.lineTo(x * scale + 0.5, N * scale);
        ctx.moveTo(0, x * scale + 0.5); ctx.lineTo(N * scale, x * scale + 0.5);
        ctx.stroke();
      }
      const kind = g <= l ? (g === 0 ? 'coarse' : `coarse (depth ${g})`) : `details d${sup(g - 1)}`;
      slabs.append(el('figure', {}, canvas, el('figcaption', { text: `k: ${kind}` })));
    }
    row.append(slabs);
    grid.append(row);
    // Entry counts per block class, and per block of depth groups.
    const table = el('table', { class: 'learn-block-table', testid: `tensor-table-${l}` });
    table.append(el('tr', {}, el('th', { text: `θ${sup(l)}` }), ...CLASS_NAMES.map((name, c) =>
      // the class's colour as a swatch beside text in the text colour (coloured text failed WCAG contrast)
      el('th', { title: name }, el('i', { class: 'learn-swatch', style: `background:${CLASS_COLORS[c]}` }), `${c}`))));
    table.prepend(el('caption', { text: 'stored entries by their number of coarse indices' }));
    table.append(el('tr', {}, el('td', { text: 'stored' }), ...classCounts.map((c) => el('td', { text: String(c) }))));
    tableBox.append(table);
    const blocks = [...blockCounts].sort(([a], [b]) => a.localeCompare(b));
    tableBox.append(el('div', { class: 'muted', text: `blocks (depths of i ≤ j ≤ k: entries): ${blocks.map(([k, c]) => `${k}: ${c}`).join(', ')}` }));
    return { level: l, stored, classCounts, blocks: Object.fromEntries(blocks), nnzFull: info.nnzFull, nnzStored: info.nnzStored };
  }

  const orderings = document.createElement('input');
  orderings.type = 'checkbox';
  orderings.checked = true;
  orderings.dataset.testid = 'tensor-orderings';
  control(layout.controls, 'all orderings', orderings);
  meshSelect.addEventListener('change', () => { s.mesh = meshSelect.value; build(); });
  schemeSelect.addEventListener('change', () => { s.scheme = schemeSelect.value; build(); });
  orderings.addEventListener('change', () => { s.allOrderings = orderings.checked; build(); });
  await build();
  return {
    dispose() { meshStage.dispose(); },
    actions: {
      /** Viewport pixels of the centre of cell (i, j) (hierarchy indices) in the picture of level l, k-group g. */
      cellCenter(l, g, i, j) {
        const rect = document.querySelector(`[data-testid="tensor-slab-${l}-${g}"]`).getBoundingClientRect();
        return [rect.left + (j + 0.5) / shown.N * rect.width, rect.top + (i + 0.5) / shown.N * rect.height];
      },
      /** A cell (i, j) of that picture with a non-zero entry, or null. */
      nonZeroCell(l, g) {
        for (let i = 0; i < shown.N; i++) for (let j = 0; j < shown.N; j++) if (entryAt(l, g, i, j).best) return [i, j];
        return null;
      },
    },
    debug: () => (result ? { ...result, mesh: s.mesh, scheme: s.scheme, allOrderings: s.allOrderings, hover,
      meshFrames: meshStage.frames ?? 0, faces: Array.from(shown.faces), markerCount: shown.markers.geometry.drawRange.count } : null),
  };
}

const SUP = '⁰¹²³⁴⁵⁶⁷⁸⁹';
function sup(n) {
  return String(n).replace(/\d/g, (d) => SUP[d]);
}
