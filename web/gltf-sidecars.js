// A .gltf chosen or dropped together with the files it refers to (its .bin buffers, as most tools
// write it by default): the buffers put into the .gltf as data: URIs, so that one self-contained
// file goes on (to the reader, a worker, the stored session). Pure of the DOM but for File / Blob.

/** The file to open of several chosen or dropped together: a .gltf with its sidecars folded in, else the first. */
export async function fileToOpen(files) {
  const list = [...(files ?? [])];
  const gltf = list.find((f) => /\.gltf$/i.test(f.name));
  if (!gltf) return list[0] ?? null;
  if (list.length === 1) return gltf;
  const text = await gltf.text();
  let doc;
  try {
    doc = JSON.parse(text);
  } catch {
    return gltf; // the reader names what is wrong with it
  }
  const byName = new Map(list.map((f) => [f.name, f]));
  let folded = 0;
  for (const buffer of Array.isArray(doc.buffers) ? doc.buffers : []) {
    if (typeof buffer?.uri !== 'string' || buffer.uri.startsWith('data:')) continue;
    const name = decodeURIComponent(buffer.uri).split(/[\\/]/).pop();
    const file = byName.get(name);
    if (!file) continue; // left as it is: the reader says which file is missing
    buffer.uri = `data:application/octet-stream;base64,${base64(new Uint8Array(await file.arrayBuffer()))}`;
    folded++;
  }
  return folded ? new File([JSON.stringify(doc)], gltf.name, { type: 'model/gltf+json' }) : gltf;
}

function base64(bytes) {
  let text = '';
  for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(text);
}

/** The reader's word for a .gltf's missing sidecar, said as the app's user can act on it. */
export function sidecarHint(message) {
  return message.replace(/\(pass it beside the \.gltf\)/, '(choose or drop it together with the .gltf)');
}
