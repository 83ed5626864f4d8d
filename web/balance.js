// Keep balance: the editor's switches for what is kept besides the volume (the centre of mass,
// "keep balance") and whose volume it is (the mesh, or its Loop limit surface), and the centre of
// mass drawn as a marker (seen through the surface: it is inside). The core computes the centroid
// (VolumeEditor.centroid); this module only moves it to the screen, once per frame at most. Both
// switches are undo steps of the session and settings of the app (kept, shared, in project files).
import * as THREE from 'three';
import { showError } from './readouts.js';

const KEPT = 0x1a7f37, FREE = 0xcf222e;
const DRAG_BUDGET_MS = 4;

function element(html) {
  const t = document.createElement('template');
  t.innerHTML = html.trim();
  return t.content.firstChild;
}

/**
 * Adds the switches above the panel and the marker to the view; follows `session`. `changeSurface`
 * makes the surface switch's editor (the app's makes a big model's in a worker; may be async).
 */
export function setUpBalance({ session, viewer, onChanged = () => {}, changeSurface = (surface) => session.setSurface(surface) }) {
  const box = element(`
    <section class="balance" data-testid="balance" aria-label="Balance and surface">
      <label class="check" title="Keep the centre of mass where it is while dragging (four constraints: the volume and the three first moments)">
        <input type="checkbox" data-testid="keep-balance"> keep balance (centre of mass)</label>
      <label title="Whose volume is kept: the triangle mesh, or the smooth Loop limit surface it stands for (closed meshes)">surface
        <select data-testid="surface-select" aria-label="surface whose volume is kept">
          <option value="mesh">mesh</option><option value="limit">limit (smooth)</option></select></label>
      <div class="muted" data-testid="centroid-readout">–</div>
    </section>`);
  document.getElementById('panel-host').before(box);
  const keep = box.querySelector('[data-testid="keep-balance"]');
  const surface = box.querySelector('[data-testid="surface-select"]');
  const readout = box.querySelector('[data-testid="centroid-readout"]');

  const marker = new THREE.Group();
  const material = new THREE.MeshBasicMaterial({ color: FREE, depthTest: false, transparent: true, opacity: 0.95 });
  const ball = new THREE.Mesh(new THREE.SphereGeometry(1, 20, 14), material);
  const ring = new THREE.Mesh(new THREE.TorusGeometry(1.9, 0.18, 8, 32), material);
  marker.add(ball, ring);
  marker.renderOrder = 10;
  ball.renderOrder = ring.renderOrder = 10;
  marker.name = 'centre of mass';
  viewer.scene.add(marker);

  let baseline = null, diagonal = 1, pending = false;
  // What the last centroid() took: a pass over the fine mesh (tens of ms at 655k vertices). Costlier than
  // DRAG_BUDGET_MS, it is not asked at every drag step but when the drag ends (a kept centre does
  // not move meanwhile; a free one follows on release).
  let centroidMs = 0, skipped = false;
  const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

  function sync() {
    keep.checked = session.keepCentroid;
    surface.value = session.surface;
    keep.disabled = session.surface === 'limit' || (session.editor !== null && !session.canKeepCentroid);
    surface.disabled = session.model !== null && !session.canKeepLimit;
    surface.parentElement.title = surface.disabled ? 'A quad mesh keeps the volume of its bilinear patches (the limit surface is that of Loop triangle meshes)'
      : 'Whose volume is kept: the triangle mesh, or the smooth Loop limit surface it stands for (closed meshes)';
    keep.parentElement.title = keep.disabled ? 'The centre of mass is kept for the mesh surface only'
      : 'Keep the centre of mass where it is while dragging (four constraints: the volume and the three first moments)';
  }

  // run in the view's frame, before it draws (viewer.requestRender(draw))
  function draw() {
    pending = false;
    if (!session.editor) return;
    if (session.dragging && centroidMs > DRAG_BUDGET_MS) {
      skipped = true;
      return;
    }
    skipped = false;
    let c;
    try {
      const started = performance.now();
      c = session.centroid();
      centroidMs = performance.now() - started;
    } catch {
      marker.visible = false;  // a solid of zero volume has no centre of mass
      readout.textContent = 'no centre of mass (zero volume)';
      return;
    }
    if (!c) {  // an editor without centroids
      marker.visible = false;
      readout.textContent = 'centre of mass: not computed for this model';
      return;
    }
    marker.visible = true;
    marker.position.set(c[0], c[1], c[2]);
    marker.quaternion.copy(viewer.camera.quaternion);  // the ring faces the viewer
    baseline ??= Array.from(c);
    const drift = distance(c, baseline) / diagonal;
    material.color.setHex(session.keepCentroid ? KEPT : FREE);
    readout.textContent = `centre of mass ${session.keepCentroid ? 'kept' : 'free'}: moved ${(100 * drift).toPrecision(2)} % of the size`;
    box.dataset.centroid = JSON.stringify(Array.from(c));
    box.dataset.baseline = JSON.stringify(baseline);
    box.dataset.drift = String(drift);
  }
  // in the view's next frame, before it draws (a frame of its own would draw a big mesh again)
  const drawSoon = () => {
    if (pending) return;
    pending = true;
    viewer.requestRender(draw);
  };

  session.addEventListener('model', () => {
    const p = session.positions();
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < p.length; i += 3) for (let k = 0; k < 3; k++) lo[k] = Math.min(lo[k], p[i + k]), hi[k] = Math.max(hi[k], p[i + k]);
    diagonal = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;
    marker.scale.setScalar(0.008 * diagonal);
    baseline = null;
    drawSoon();
  });
  session.addEventListener('editor', () => { sync(); drawSoon(); });
  session.addEventListener('dragend', () => { if (skipped) drawSoon(); });
  session.addEventListener('change', ({ detail }) => {
    if (detail.reason === 'undo' || detail.reason === 'redo') sync(); // a keep or surface step undone
    drawSoon();
  });
  viewer.controls?.addEventListener('change', () => marker.quaternion.copy(viewer.camera.quaternion));

  keep.addEventListener('change', () => {
    try {
      session.setKeepCentroid(keep.checked); // one undo step
      if (keep.checked) baseline = Array.from(session.referenceCentroid());
    } catch (e) {
      showError(`Balance could not be kept: ${e.message}`);
    }
    sync();
    drawSoon();
    onChanged();
  });
  surface.addEventListener('change', async () => {
    try {
      await changeSurface(surface.value);
    } catch (e) {
      showError(`The ${surface.value} surface cannot be used: ${e.message}`);
    }
    sync();
    drawSoon();
    onChanged();
  });
  sync();
  return { marker, draw, sync };
}
