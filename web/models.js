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
