// A soft shadow of the model on a floor under it: a light straight above (no light of its own, it
// only casts: intensity 0) renders the model's depth into a blurred variance shadow map, and an
// invisible floor (THREE.ShadowMaterial) shows only the shadow. It grounds the model in the view.
// The floor sits under the model as it opens and stays there while it is edited; it writes no depth
// (a handle dragged below it is not hidden) and is not pickable (handles are picked on the screen).
// The shadow map is drawn again when the shape changed, at most every THROTTLE_MS (a blurred shadow
// lagging a drag by a few frames is not seen; software WebGL draws fewer passes).
import * as THREE from 'three';

const MAP_SIZE = 256;
const BLUR_RADIUS = 6;
const OPACITY = 0.28;
const THROTTLE_MS = 150;

export class FloorShadow {
  /** @param {THREE.WebGLRenderer} renderer  @param {THREE.Scene} scene */
  constructor(renderer, scene) {
    this.renderer = renderer;
    renderer.shadowMap.enabled = true;
    renderer.shadowMap.type = THREE.VSMShadowMap;
    renderer.shadowMap.autoUpdate = false;
    this.light = new THREE.DirectionalLight(0xffffff, 0);
    this.light.castShadow = true;
    this.light.shadow.mapSize.set(MAP_SIZE, MAP_SIZE);
    this.light.shadow.radius = BLUR_RADIUS;
    this.light.shadow.blurSamples = 8;
    // VSM draws the floor (a receiver) into the map too, at its own depth, kept as a half float: where
    // that rounds below the floor's depth the floor shadows itself (a grey floor with a lit ring round
    // the model: the npm teapot). The bias is 4 times that rounding at depths 0.5-1 (2^-11 / 2) and a
    // quarter of the model's gap to the floor (0.02 r over a far plane 5 r away): its shadow stays.
    this.light.shadow.bias = -0.001;
    this.floor = new THREE.Mesh(new THREE.PlaneGeometry(1, 1).rotateX(-Math.PI / 2),
      new THREE.ShadowMaterial({ opacity: OPACITY, depthWrite: false }));
    this.floor.receiveShadow = true;
    this.floor.renderOrder = -1;
    this.floor.name = 'floor shadow';
    scene.add(this.light, this.light.target, this.floor);
    this.dirty = false;
    this.lastUpdate = -Infinity;
    this.updates = 0;
    this.timer = null;
    this.onLate = null; // called when a throttled update is due (the viewer requests a frame)
  }

  /** Puts the floor under the model (positions: 3 per vertex) and the light's view around it. */
  fit(positions) {
    const box = new THREE.Box3();
    const p = new THREE.Vector3();
    const stride = Math.max(1, Math.floor(positions.length / 3 / 50_000));
    for (let i = 0; i < positions.length; i += 3 * stride) box.expandByPoint(p.set(positions[i], positions[i + 1], positions[i + 2]));
    if (box.isEmpty()) return;
    const center = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3());
    const radius = Math.max(size.length() / 2, 1e-9);
    const y = box.min.y - 0.02 * radius;
    this.floor.position.set(center.x, y, center.z);
    this.floor.scale.setScalar(6 * radius);
    this.light.position.set(center.x, box.max.y + 2 * radius, center.z);
    this.light.target.position.set(center.x, y, center.z);
    const camera = this.light.shadow.camera;
    // room for edits that pull the model out to twice its size
    Object.assign(camera, { left: -2 * radius, right: 2 * radius, top: 2 * radius, bottom: -2 * radius, near: 0.01 * radius, far: 5 * radius });
    camera.updateProjectionMatrix();
    this.light.updateMatrixWorld();
    this.light.target.updateMatrixWorld();
    this.changed();
  }

  /** The shape changed: the shadow is drawn again with the next frame (throttled for big meshes). */
  changed() {
    this.dirty = true;
  }

  /** Before a frame: whether the shadow map is drawn in it. */
  beforeRender(now = performance.now()) {
    if (!this.dirty || !this.floor.visible) return;
    if (now - this.lastUpdate < THROTTLE_MS) {
      // mid-drag: this frame keeps the last shadow; one more frame when it is due
      clearTimeout(this.timer);
      this.timer = setTimeout(() => this.onLate?.(), THROTTLE_MS - (now - this.lastUpdate));
      return;
    }
    this.dirty = false;
    this.lastUpdate = now;
    this.updates++;
    this.renderer.shadowMap.needsUpdate = true;
  }

  setVisible(visible) {
    this.floor.visible = visible;
    this.light.castShadow = visible;
    this.changed();
  }
}
