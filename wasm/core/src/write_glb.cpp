// GLB export: one node, one indexed triangle primitive (float32 POSITION with its bounds,
// area-weighted vertex NORMAL, uint32 indices) in a single BIN chunk.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf_document.h"
#include "mrvol/error.h"
#include "mrvol/io_formats.h"

namespace mrvol {

namespace {

template <class T>
void append(std::string& out, const T* data, size_t n) {
  out.append(reinterpret_cast<const char*>(data), n * sizeof(T));
}

void putU32(std::string& out, uint32_t v) { append(out, &v, 1); }

}  // namespace

std::string writeGlb(const TriangleMesh& mesh) {
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  if (mesh.positions.size() != 3 * nv || mesh.faces.size() != 3 * nf) throw Error("writeGlb: arrays are not triples");
  if (nf == 0) throw Error("writeGlb: the mesh has no faces");
  for (uint32_t i : mesh.faces)
    if (i >= nv) throw Error("writeGlb: a face refers to vertex " + std::to_string(i) + " of " + std::to_string(nv));
  std::vector<float> positions(3 * nv);
  float lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = std::numeric_limits<float>::max(), hi[k] = -lo[k];
  for (size_t i = 0; i < 3 * nv; ++i) {
    const float x = float(mesh.positions[i]);
    if (!std::isfinite(x)) throw Error("writeGlb: vertex " + std::to_string(i / 3) + " does not fit a float32");
    positions[i] = x;
    lo[i % 3] = std::fmin(lo[i % 3], x), hi[i % 3] = std::fmax(hi[i % 3], x);
  }
  // Area-weighted normals (the cross product's length is twice the area).
  std::vector<double> accumulated(3 * nv, 0.0);
  const double* p = mesh.positions.data();
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t a = mesh.faces[3 * f], b = mesh.faces[3 * f + 1], c = mesh.faces[3 * f + 2];
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) u[k] = p[3 * b + k] - p[3 * a + k], v[k] = p[3 * c + k] - p[3 * a + k];
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    for (uint32_t corner : {a, b, c})
      for (int k = 0; k < 3; ++k) accumulated[3 * corner + k] += n[k];
  }
  std::vector<float> normals(3 * nv);
  for (size_t v = 0; v < nv; ++v) {
    const double* n = &accumulated[3 * v];
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k) normals[3 * v + k] = length > 0 && std::isfinite(length) ? float(n[k] / length) : (k == 2 ? 1.f : 0.f);
  }
  const size_t positionBytes = 12 * nv, normalBytes = 12 * nv, indexBytes = 4 * mesh.faces.size();
  using nlohmann::json;
  json doc = {
      {"asset", {{"version", "2.0"}, {"generator", "mrvol"}}},
      {"scene", 0},
      {"scenes", json::array({{{"nodes", {0}}}})},
      {"nodes", json::array({{{"mesh", 0}}})},
      {"meshes", json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}},
                                                            {"indices", 2},
                                                            {"mode", 4}}})}}})},
      {"accessors", json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", nv}, {"type", "VEC3"},
                                  {"min", {lo[0], lo[1], lo[2]}}, {"max", {hi[0], hi[1], hi[2]}}},
                                 {{"bufferView", 1}, {"componentType", 5126}, {"count", nv}, {"type", "VEC3"}},
                                 {{"bufferView", 2}, {"componentType", 5125}, {"count", mesh.faces.size()}, {"type", "SCALAR"}}})},
      {"bufferViews", json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", positionBytes}, {"target", 34962}},
                                   {{"buffer", 0}, {"byteOffset", positionBytes}, {"byteLength", normalBytes}, {"target", 34962}},
                                   {{"buffer", 0}, {"byteOffset", positionBytes + normalBytes}, {"byteLength", indexBytes},
                                    {"target", 34963}}})},
      {"buffers", json::array({{{"byteLength", positionBytes + normalBytes + indexBytes}}})},
  };
  std::string bin;
  bin.reserve(positionBytes + normalBytes + indexBytes);
  append(bin, positions.data(), positions.size());
  append(bin, normals.data(), normals.size());
  append(bin, mesh.faces.data(), mesh.faces.size());
  return gltf::glbContainer(doc.dump(), bin);
}

namespace gltf {

std::string glbContainer(std::string text, std::string_view bin) {
  while (text.size() % 4) text.push_back(' ');  // chunks are 4-byte aligned: JSON pads with spaces
  const size_t binPadded = (bin.size() + 3) / 4 * 4;
  const uint64_t total = 12 + 8 + text.size() + 8 + binPadded;
  if (total > 0xffffffffu) throw Error("writeGlb: the mesh is too large for a GLB file (4 GB)");
  std::string out;
  out.reserve(size_t(total));
  out.append("glTF", 4);
  putU32(out, 2);
  putU32(out, uint32_t(total));
  putU32(out, uint32_t(text.size()));
  putU32(out, 0x4E4F534A);  // JSON
  out += text;
  putU32(out, uint32_t(binPadded));
  putU32(out, 0x004E4942);  // BIN
  out.append(bin);
  out.append(binPadded - bin.size(), '\0');
  return out;
}

}  // namespace gltf

}  // namespace mrvol
