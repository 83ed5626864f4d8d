// How big a mesh this page opens, and the message when a file is bigger. The editor keeps the mesh,
// its hierarchy and the editor in one WebAssembly heap (at most 4 GB; about 500 bytes per vertex
// while opening), beside the drawing's buffers: 3 million vertices leave room (the 2.6M-vertex
// spiky ball opens); beyond, a tab runs out of memory. The CLI (mrvol) has no such limit.
export const MAX_VERTICES = 3_000_000;
// A file over this size is refused before it is read (an OBJ of 3M vertices is about 250 MB).
export const MAX_FILE_BYTES = 400 * 2 ** 20;

const millions = (n) => `${(n / 1e6).toFixed(n >= 1e7 ? 0 : 1)} million`;

/** The message for a mesh too big for the page: { vertices, claimed } or { bytes }. */
export function sizeMessage({ vertices = null, claimed = false, bytes = null }) {
  const what = vertices !== null
    ? `${claimed ? 'says it has' : 'has'} ${millions(vertices)} vertices`
    : `is ${Math.round(bytes / 2 ** 20)} MB`;
  return `this file ${what}: too big to edit in a browser tab (at most ${millions(MAX_VERTICES)} vertices, ` +
    `files up to ${MAX_FILE_BYTES / 2 ** 20} MB). Simplify it first, or use the command line (mrvol), which has no such limit.`;
}

// An OBJ bigger than this has its vertex lines counted before it is parsed: a file that cannot
// open says so in a second, not after the parser has filled the memory (an OBJ of MAX_VERTICES
// vertices and their triangles takes at least ~60 MB: 'v 0 0 0' and 'f 1 2 3' lines).
const OBJ_COUNT_BYTES = 50 * 2 ** 20;

/** The number of OBJ vertex lines ('v' then a space or tab at a line's start); a fast byte scan. */
export function objVertexLines(bytes) {
  const isVertex = (i) => bytes[i] === 0x76 && (bytes[i + 1] === 0x20 || bytes[i + 1] === 0x09);
  let count = isVertex(0) ? 1 : 0;
  for (let at = bytes.indexOf(0x0a); at >= 0; at = bytes.indexOf(0x0a, at + 1)) if (isVertex(at + 1)) count++;
  return count;
}

/**
 * The vertex count a file's header claims, before anything is parsed (PLY's element vertex, OFF's
 * counts, a binary STL's triangle count, about twice its welded vertices; a big OBJ's vertex
 * lines, counted), or 0 when it says none.
 */
export function claimedVertices(bytes, name = '') {
  const head = new TextDecoder('latin1').decode(bytes.subarray(0, Math.min(bytes.byteLength, 4096)));
  // A count the file's length cannot hold (at least 12 bytes a binary vertex, 6 an ASCII one) is a
  // lie the reader reports, not a size.
  const plausible = (count, bytesEach) => (bytes.byteLength >= count * bytesEach ? count : 0);
  if (head.startsWith('ply')) {
    const m = /element\s+vertex\s+(\d+)/.exec(head);
    return m ? plausible(Number(m[1]), /format\s+binary/.test(head) ? 12 : 6) : 0;
  }
  const off = /^\s*[CN]?OFF\s+(?:#[^\n]*\n\s*)*(\d+)\s+(\d+)/.exec(head);
  if (off) return plausible(Number(off[1]), 6);
  if (/\.stl$/i.test(name) && bytes.byteLength >= 84 && !/^solid[\s\S]*facet/.test(head)) {
    const triangles = new DataView(bytes.buffer, bytes.byteOffset + 80, 4).getUint32(0, true);
    // a count the length contradicts is the reader's to report (truncated), not a size
    return bytes.byteLength >= 84 + 50 * triangles ? Math.floor(triangles / 2) : 0;
  }
  if (bytes.byteLength > OBJ_COUNT_BYTES && (/\.obj$/i.test(name) || /^\s*(#|v\s|o\s|g\s|mtllib)/.test(head))) return objVertexLines(bytes);
  return 0;
}
