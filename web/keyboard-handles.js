// Handles from the keyboard: the canvas takes focus (Tab); there Tab / Shift+Tab (or ] and [) select
// the next / previous handle (Tab past the last one leaves the canvas), and the arrow keys move the
// selected handles on the screen plane by 2% of the model's radius (Shift: 10%), one undo step each.
import { THREE } from './viewer.js';

const right = new THREE.Vector3();
const up = new THREE.Vector3();

/**
 * app: the editor (viewer, session, selection); onMoved() after a nudge (the view is drawn here);
 * canNudge() says whether the editor takes edits now.
 */
export function setUpKeyboardHandles({ app, onMoved, canNudge }) {
  const canvas = app.viewer.canvas;
  canvas.tabIndex = 0;
  canvas.setAttribute('role', 'application');
  const describe = () => {
    const n = app.session?.cageSize ?? 0;
    const selected = [...app.selection];
    canvas.setAttribute('aria-label', `3D view of ${app.model?.name ?? 'the model'}: ${n} handles` +
      (selected.length ? `, handle ${selected.join(', ')} selected` : '') +
      '. Tab selects the next handle, the arrow keys move it, F frames the model, ? lists every key.');
  };
  describe();

  const select = (index) => {
    app.selection = index === null ? new Set() : new Set([index]);
    app.viewer.setSelection(app.selection);
    describe();
  };

  canvas.addEventListener('focus', describe);
  canvas.addEventListener('keydown', (e) => {
    const n = app.session?.cageSize ?? 0;
    if (!n || e.ctrlKey || e.metaKey || e.altKey) return;
    const current = app.selection.size ? Math.max(...app.selection) : -1;
    if (e.key === 'Tab' || e.key === ']' || e.key === '[') {
      const back = e.key === '[' || (e.key === 'Tab' && e.shiftKey);
      const next = back ? current - 1 : current + 1;
      if (e.key === 'Tab' && (next >= n || next < 0 || (back && current === -1))) {
        select(null); // leave the canvas the usual way
        return;
      }
      e.preventDefault();
      select(((next % n) + n) % n);
      return;
    }
    const arrows = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, 1], ArrowDown: [0, -1] };
    const direction = arrows[e.key];
    if (!direction || app.selection.size === 0 || !canNudge()) return;
    e.preventDefault();
    const radius = app.viewer.mesh?.geometry.boundingSphere?.radius ?? 1;
    const step = radius * (e.shiftKey ? 0.1 : 0.02);
    app.viewer.camera.updateMatrixWorld();
    right.setFromMatrixColumn(app.viewer.camera.matrixWorld, 0).multiplyScalar(direction[0] * step);
    up.setFromMatrixColumn(app.viewer.camera.matrixWorld, 1).multiplyScalar(direction[1] * step);
    const delta = right.add(up);
    app.session.preserve = app.settings.preserve;
    app.session.tolerance = app.settings.tolerance;
    if (app.session.moveHandles([...app.selection], [delta.x, delta.y, delta.z])) onMoved();
    describe();
  });
  return { describe };
}
