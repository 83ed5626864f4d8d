// A TypeScript page module using mrvol/three (type-checked with `tsc --strict --noEmit`; needs
// `@types/three` beside `three`): the component in a scene of the host's own, rendered on change.
import * as THREE from 'three';
import { createMrvol } from 'mrvol';
import type { EditReport } from 'mrvol';
import { VolumeEditControls, bounds, frameSphere } from 'mrvol/three';

/** Opens an OBJ in `container` and returns the component; every step's report goes to `onStep`. */
export async function openEditor(container: HTMLElement, objUrl: string,
                                 onStep: (report: EditReport) => void): Promise<VolumeEditControls> {
  const renderer = new THREE.WebGLRenderer({ antialias: true });
  renderer.setSize(container.clientWidth, container.clientHeight);
  container.append(renderer.domElement);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(35, container.clientWidth / container.clientHeight, 0.01, 100);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x606070, 2.5));

  const mrvol = await createMrvol();
  const mesh = mrvol.readObj(await (await fetch(objUrl)).text());
  const editor = new VolumeEditControls(mrvol, camera, renderer, mesh, { level: 0, scheme: 'loop', tolerance: 1e-6 });
  scene.add(editor.object);
  frameSphere(camera, bounds(mesh.positions));

  editor.addEventListener('drag', (event) => onStep(event.report));
  editor.addEventListener('change', () => renderer.render(scene, camera));
  editor.addEventListener('error', (event) => console.warn(event.message));
  renderer.render(scene, camera);
  return editor;
}
