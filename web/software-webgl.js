// Whether this browser's WebGL is drawn in software (SwiftShader: Chromium without a GPU, e.g.
// headless). There a frame of a big mesh takes seconds, and multisampling (antialias) multiplies
// it: at 1.3M triangles, 1200 x 800, the main pass took 9-10 s with 4 samples and 3-7 s without
// (bench/web-big-trace.mjs, docs/big-file-frames.md). Used only for choices a GPU user never sees.
let answer = null;

/** True when WebGL2 (or WebGL) here is SwiftShader; asked once, of a small throw-away context. */
export function softwareWebGL() {
  if (answer !== null) return answer;
  answer = false;
  try {
    const gl = document.createElement('canvas').getContext('webgl2') ?? document.createElement('canvas').getContext('webgl');
    if (!gl) return answer;
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    const renderer = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
    answer = /swiftshader/i.test(String(renderer));
    gl.getExtension('WEBGL_lose_context')?.loseContext(); // its resources go now, not at GC
  } catch {
    // no answer: treated as a GPU
  }
  return answer;
}
