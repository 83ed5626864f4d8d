// The room light of the editor's surface (web/viewer.js): three.js's RoomEnvironment as a light
// probe, its spherical harmonics measured once (web/room-light-measure.js, a 128 px cube map) and
// kept here. It replaced the room prefiltered for image-based light (PMREMGenerator, 256 px cube
// faces with six blurred mip levels since three r18x) when that prefiltering was found to hold
// software WebGL (Chromium without a GPU: headless, or a blocklisted GPU) for 3-5 s after each
// page's first second, every frame until then waiting for it. The probe costs nothing to make, and
// on the editor's matte surface (roughness 0.6, no metal) it draws within 12 of 255 levels of the
// prefiltered room (1 on average; the room's blurred reflections were all it added).
import * as THREE from 'three';

/** The room's 9 spherical-harmonic coefficients (the room is grey: one value for red, green and blue). */
export const ROOM_LIGHT_SH = [3.744266, 1.755191, 1.637932, 0.275053, 0.214929, 1.089037, 1.223425, -0.34859, -0.610302];

/** A light probe of the room at `intensity` (what scene.environmentIntensity was for the prefiltered room). */
export function roomLightProbe(intensity) {
  const sh = new THREE.SphericalHarmonics3();
  sh.coefficients.forEach((c, i) => c.setScalar(ROOM_LIGHT_SH[i]));
  const probe = new THREE.LightProbe(sh, intensity);
  probe.name = 'room light';
  return probe;
}
