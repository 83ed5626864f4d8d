// The sample models (public/models/NAME.obj), fetched by the editor and the teaching views alike.

export function modelUrl(name) {
  return `${import.meta.env.BASE_URL}models/${encodeURIComponent(name)}.obj`;
}

/** A sample model's OBJ text; rejects with a message naming the model when there is none. */
export async function fetchSample(name) {
  if (!/^[\w.-]+$/.test(name)) throw new Error(`'${name}' is not a model name`);
  const response = await fetch(modelUrl(name));
  if (!response.ok) throw new Error(`there is no sample model '${name}' (HTTP ${response.status})`);
  return response.text();
}

// Without 1-to-4 splits every vertex is a handle: fine for a small base mesh, not for a big one.
const MAX_FLAT_VERTICES = 64;

/**
 * The OBJ text of a model source: { text } as is, a prefetched sample ({ prefetch: Promise of the
 * text or an Error }), a sample by name, or a File ({ file }).
 */
export async function sourceText(source) {
  const prefetched = source.prefetch ? await source.prefetch : undefined;
  if (prefetched instanceof Error) throw prefetched;
  return source.text ?? prefetched ?? (source.kind === 'sample' ? await fetchSample(source.name) : await source.file.text());
}

/**
 * Reads an OBJ and opens it for editing (openParsed); a file that does not read throws its reason
 * with `offer` null.
 */
export function openObj(mrvol, text) {
  let mesh;
  try {
    mesh = mrvol.readObj(text);
  } catch (e) {
    e.offer = null;
    throw e;
  }
  return openParsed(mrvol, mesh);
}

/**
 * Opens a mesh read from a file ({ positions, faces }, any format) for editing: the MultiresMesh
 * (the caller's) and its info; with `opened` (a MultiresMesh of this mesh) that one, with
 * `hierarchy` (MultiresMesh.hierarchyArrays() of this mesh) by the fast path. Otherwise throws the reason, with `offer`: 'remesh' (it opened but is
 * not semi-regular), 'repair' (it is not a closed 2-manifold, a raw scan, or has holes), or null (nothing would help).
 */
export function openParsed(mrvol, mesh, { hierarchy = null, opened = null } = {}) {
  let mr = null, info;
  try {
    // what the file's worker found (open-worker.js): the mesh opened there, or its hierarchy: no
    // validation or detection here again
    mr = opened ?? (hierarchy ? mrvol.openMeshWithHierarchy(mesh, hierarchy) : mrvol.openMesh(mesh));
    info = mr.info();
    // A mesh with holes and no levels: the remesher needs it closed (the repair offered), and as it is it encloses no volume.
    if (info.levels === 0 && !info.closed)
      throw new mrvol.MrvolError(`this mesh has holes (${info.boundaryEdges} boundary edges), so it encloses no volume to keep, ` +
                                 'and it is not semi-regular (no 1-to-4 subdivision levels)');
    if (info.closed) noVolumeProblem(mrvol, mesh.positions, info);
    if (info.levels === 0 && info.vertices > MAX_FLAT_VERTICES)
      throw new mrvol.MrvolError(
        `this mesh is not semi-regular: no 1-to-4 subdivision levels were found in its ${info.vertices} vertices, ` +
        'so it has no coarse cage to edit (mrvol edits meshes made by repeated 1-to-4 splits of a base mesh)');
    return { mr, info };
  } catch (e) {
    // an open flat mesh is repaired first (its holes closed), as one that does not open at all
    if (!('offer' in e)) e.offer = mr !== null && info?.levels === 0 ? (info.closed ? 'remesh' : 'repair') : mr === null ? 'repair' : null;
    mr?.delete();
    throw e;
  }
}

/**
 * Throws when a closed mesh encloses no volume: all its vertices at one point (nothing to see or
 * drag), or a flat surface (nothing to keep). Its volume is cubic in its size: compared with the
 * bounding box's diagonal cubed.
 */
function noVolumeProblem(mrvol, positions, info) {
  const low = [Infinity, Infinity, Infinity], high = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; i += 3)
    for (let k = 0; k < 3; k++) low[k] = Math.min(low[k], positions[i + k]), high[k] = Math.max(high[k], positions[i + k]);
  const diagonal = Math.hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);
  if (diagonal === 0)
    throw Object.assign(new mrvol.MrvolError(`all ${info.vertices} vertices of this mesh are at one point (${low.join(', ')}): ` +
                                             'it has no shape to show or edit'), { offer: null });
  if (Math.abs(info.volume) <= 1e-12 * diagonal ** 3)
    throw Object.assign(new mrvol.MrvolError(`this mesh encloses no volume (${info.volume}): its surface lies flat, ` +
                                             'like a sheet folded onto itself, so there is no volume to keep'), { offer: null });
}

/**
 * A semi-regular quad OBJ (every face a quad; Catmull-Clark levels found, or a base small enough to
 * edit vertex by vertex) opened as a quad model (lib/quad.mjs): { mr, info }. null when the file is
 * not one: it then opens as triangles (each polygon split), with the remesh offer when that fails.
 * model: { format, text? | bytes? } (the file), mesh: what readObj / readMesh made of it.
 */
export function openQuadObj(mrvol, model, mesh) {
  const source = model.text ?? model.bytes;
  // a triangle file is not read twice: its first face line decides
  if (model.format !== 'obj' || source === undefined || mesh.faces.length % 6 !== 0 || firstFaceCorners(source) !== 4) return null;
  let quads, mr = null;
  try {
    quads = mrvol.readObjQuads(source);
  } catch {
    return null; // not all quads
  }
  try {
    mr = mrvol.openQuadMesh(quads);
    const info = mr.info();
    if (info.levels > 0 || info.vertices <= MAX_FLAT_VERTICES) return { mr, info };
  } catch { /* not a valid quad mesh: the triangle way says why */ }
  mr?.delete();
  return null;
}

/** The corner count of an OBJ's first face line (`f a b c d`), 0 when it has none. */
export function firstFaceCorners(source) {
  const bytes = typeof source === 'string' ? null : source;
  const at = typeof source === 'string' ? source.search(/^f[ \t]/m) : faceLineStart(bytes);
  if (at < 0) return 0;
  const end = typeof source === 'string' ? source.indexOf('\n', at) : bytes.indexOf(10, at);
  const line = typeof source === 'string' ? source.slice(at, end < 0 ? undefined : end)
    : new TextDecoder().decode(bytes.subarray(at, end < 0 ? undefined : end));
  return line.split('#')[0].trim().split(/\s+/).length - 1;
}

// Where the first line starting with `f ` begins in OBJ bytes, or -1.
function faceLineStart(bytes) {
  // from one 'f' to the next (indexOf: a native scan; numbers have no 'f')
  for (let i = bytes.indexOf(102); i >= 0 && i + 1 < bytes.length; i = bytes.indexOf(102, i + 1))
    if ((bytes[i + 1] === 32 || bytes[i + 1] === 9) && (i === 0 || bytes[i - 1] === 10)) return i;
  return -1;
}

/** A file's name without its mesh extension (the base of the names of its exports and remeshed copy). */
export function baseNameOf(name) {
  return name.replace(/\.(obj|stl|ply|off|coff|noff|gltf|glb|json)$/i, '').replace(/\.mrvol$/i, '');
}
