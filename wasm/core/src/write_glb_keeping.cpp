// GLB export that keeps a glTF / GLB source's data: the edited positions go back into each
// primitive's POSITION (in its node's frame), NORMAL is recomputed where the source has it, and
// everything else (materials, textures, texture coordinates, colours, skins, animations, extras)
// is the source's JSON and bytes. New accessor data is appended to the one BIN chunk; the old
// bytes stay where they are (other accessors may share their buffer views).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "gltf_document.h"
#include "io_common.h"
#include "mrvol/error.h"
#include "mrvol/io_formats.h"

namespace mrvol {

namespace {

using gltf::json;
using gltf::Matrix;
using io::count;

// The inverse of the upper 3x3 of a column-major 4x4 (its columns are the images of the axes).
std::array<double, 9> inverse3(const Matrix& m) {
  const double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6], i = m[10];
  const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  // Row-major result r[row * 3 + col].
  return {(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det,
          (f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det,
          (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det};
}

// Float32 VEC3 data appended to the BIN chunk as a new buffer view; returns its index.
size_t appendView(json& root, std::string& bin, const std::vector<float>& values) {
  while (bin.size() % 4) bin.push_back('\0');
  json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", 4 * values.size()}, {"target", 34962}};
  bin.append(reinterpret_cast<const char*>(values.data()), 4 * values.size());
  root["bufferViews"].push_back(view);
  return root["bufferViews"].size() - 1;
}

// Points an accessor at new float32 VEC3 data (dense: sparse and normalization dropped).
void replaceAccessor(json& root, std::string& bin, size_t accessor, const std::vector<float>& values, bool bounds) {
  json& a = root["accessors"][accessor];
  a["bufferView"] = appendView(root, bin, values);
  a.erase("byteOffset");
  a.erase("sparse");
  a.erase("normalized");
  a["componentType"] = 5126;
  a.erase("min");
  a.erase("max");
  if (bounds && !values.empty()) {
    std::array<float, 3> lo{values[0], values[1], values[2]}, hi = lo;
    for (size_t i = 0; i < values.size(); ++i) lo[i % 3] = std::min(lo[i % 3], values[i]), hi[i % 3] = std::max(hi[i % 3], values[i]);
    a["min"] = lo;
    a["max"] = hi;
  }
}

std::string writeKeeping(std::string_view source, MeshFormat sourceFormat, const GltfResources& resources,
                         const TriangleMesh& edited) {
  if (sourceFormat != MeshFormat::Gltf && sourceFormat != MeshFormat::Glb)
    throw Error(std::string("writeGlb: the source is ") + formatName(sourceFormat) + ", not glTF or GLB");
  const gltf::Document d = sourceFormat == MeshFormat::Glb ? gltf::openGlb(source, resources) : gltf::openGltf(source, resources);
  gltf::SceneGeometry scene = gltf::collectScene(d);
  TriangleMesh welded = scene.mesh;
  std::vector<uint32_t> outputOf;  // scene vertex -> edited vertex
  weldExactPositions(welded, nullptr, &outputOf);
  if (welded.vertexCount() != edited.vertexCount() || welded.faces != edited.faces)
    throw Error("writeGlb: the mesh's triangles differ from its source glTF's (" + count(edited.faceCount()) + " vs " +
                count(welded.faceCount()) + " triangles, " + count(edited.vertexCount()) + " vs " + count(welded.vertexCount()) +
                " vertices): write it without the source");
  for (double x : edited.positions)
    if (!std::isfinite(x)) throw Error("writeGlb: a position is not finite");

  // New local positions per POSITION accessor; vertices no triangle uses keep theirs.
  std::map<size_t, std::vector<double>> positions;
  std::map<size_t, std::vector<char>> placed;
  for (const gltf::PrimitiveUse& use : scene.uses) {
    auto [it, fresh] = positions.try_emplace(use.positionAccessor);
    if (fresh) {
      it->second = gltf::readAccessor(d, use.positionAccessor, 3, "POSITION");
      placed[use.positionAccessor].assign(it->second.size() / 3, 0);
    }
    std::vector<double>& local = it->second;
    std::vector<char>& done = placed[use.positionAccessor];
    const std::array<double, 9> inv = inverse3(use.world);
    for (size_t v = 0; v < use.outputOf.size(); ++v) {
      if (use.outputOf[v] == UINT32_MAX) continue;
      const double* p = &edited.positions[3 * outputOf[use.outputOf[v]]];
      const double q[3] = {p[0] - use.world[12], p[1] - use.world[13], p[2] - use.world[14]};
      double x[3];
      for (int r = 0; r < 3; ++r) x[r] = inv[3 * r] * q[0] + inv[3 * r + 1] * q[1] + inv[3 * r + 2] * q[2];
      if (done[v]) {
        const double scale = std::max({std::fabs(x[0]), std::fabs(x[1]), std::fabs(x[2]), 1e-30});
        for (int k = 0; k < 3; ++k)
          if (std::fabs(local[3 * v + k] - x[k]) > 1e-6 * scale)
            throw Error("writeGlb: accessor " + count(use.positionAccessor) + " (mesh " + count(use.mesh) +
                        ") is shared by nodes the edit moves differently: write it without the source");
        continue;
      }
      for (int k = 0; k < 3; ++k) local[3 * v + k] = x[k];
      done[v] = 1;
    }
  }

  // Normals: area-weighted sums of the edited triangles (world frame) over the copies of a vertex
  // that had the same source normal, so a crease the source split stays split.
  std::map<size_t, std::vector<double>> normals;
  for (const gltf::PrimitiveUse& use : scene.uses) {
    if (use.normalAccessor < 0) continue;
    const size_t na = size_t(use.normalAccessor);
    const std::vector<double> original = gltf::readAccessor(d, na, 3, "NORMAL");
    if (original.size() != use.outputOf.size() * 3)
      throw Error("writeGlb: NORMAL accessor " + count(na) + " has another count than its POSITION");
    using Key = std::tuple<uint32_t, float, float, float>;
    std::map<Key, std::array<double, 3>> sums;
    auto keyOf = [&](uint32_t v) {
      return Key{outputOf[use.outputOf[v]], float(original[3 * v]), float(original[3 * v + 1]), float(original[3 * v + 2])};
    };
    for (size_t t = 0; t < use.triangles.size(); t += 3) {
      const double* a = &edited.positions[3 * outputOf[use.outputOf[use.triangles[t]]]];
      const double* b = &edited.positions[3 * outputOf[use.outputOf[use.triangles[t + 1]]]];
      const double* c = &edited.positions[3 * outputOf[use.outputOf[use.triangles[t + 2]]]];
      const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      // In the source's winding: a mirroring node reversed it on reading, so the cross product flips back.
      const double det = use.world[0] * (use.world[5] * use.world[10] - use.world[9] * use.world[6]) -
                         use.world[4] * (use.world[1] * use.world[10] - use.world[9] * use.world[2]) +
                         use.world[8] * (use.world[1] * use.world[6] - use.world[5] * use.world[2]);
      const double sign = det < 0 ? -1 : 1;
      const double n[3] = {sign * (u[1] * w[2] - u[2] * w[1]), sign * (u[2] * w[0] - u[0] * w[2]), sign * (u[0] * w[1] - u[1] * w[0])};
      for (size_t k = 0; k < 3; ++k) {
        auto& s = sums.try_emplace(keyOf(use.triangles[t + k]), std::array<double, 3>{0, 0, 0}).first->second;
        for (int j = 0; j < 3; ++j) s[j] += n[j];
      }
    }
    auto [it, fresh] = normals.try_emplace(na, original);
    std::vector<double>& out = it->second;
    for (size_t v = 0; v < use.outputOf.size(); ++v) {
      if (use.outputOf[v] == UINT32_MAX) continue;
      auto found = sums.find(keyOf(uint32_t(v)));
      if (found == sums.end()) continue;
      const auto& s = found->second;
      // World normal to the node's frame: n_local is M^T n_world (normals go by the inverse transpose).
      double l[3];
      for (int r = 0; r < 3; ++r) l[r] = use.world[4 * r] * s[0] + use.world[4 * r + 1] * s[1] + use.world[4 * r + 2] * s[2];
      const double length = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
      if (length > 0 && std::isfinite(length))
        for (int k = 0; k < 3; ++k) out[3 * v + k] = l[k] / length;
    }
  }

  // One buffer: the source buffers in order (8-byte aligned), then the new data.
  json root = d.root;
  std::string bin;
  std::vector<uint64_t> offsetOf;
  for (std::string_view b : d.buffers) {
    while (bin.size() % 8) bin.push_back('\0');
    offsetOf.push_back(bin.size());
    bin.append(b);
  }
  if (root.contains("bufferViews"))
    for (json& view : root["bufferViews"]) {
      const size_t buffer = view.value("buffer", size_t(0));
      view["byteOffset"] = view.value("byteOffset", uint64_t(0)) + offsetOf.at(buffer);
      view["buffer"] = 0;
    }
  else
    root["bufferViews"] = json::array();
  for (auto& [accessor, local] : positions) {
    std::vector<float> values(local.begin(), local.end());
    for (float x : values)
      if (!std::isfinite(x)) throw Error("writeGlb: a position does not fit a float32");
    replaceAccessor(root, bin, accessor, values, true);
  }
  for (auto& [accessor, n] : normals) replaceAccessor(root, bin, accessor, std::vector<float>(n.begin(), n.end()), false);
  while (bin.size() % 4) bin.push_back('\0');
  root["buffers"] = json::array({{{"byteLength", bin.size()}}});
  json& asset = root["asset"];
  if (asset.is_object()) asset["generator"] = "mrvol (edited from " + asset.value("generator", std::string("a glTF file")) + ")";
  return gltf::glbContainer(root.dump(), bin);
}

}  // namespace

std::string writeGlbKeeping(std::string_view source, MeshFormat sourceFormat, const GltfResources& resources,
                            const TriangleMesh& edited) {
  try {
    return writeKeeping(source, sourceFormat, resources, edited);
  } catch (const nlohmann::json::exception& e) {  // parts of the source JSON the reader did not need
    throw Error(std::string("writeGlb: the source glTF's JSON: ") + e.what());
  } catch (const std::out_of_range&) {
    throw Error("writeGlb: a bufferView of the source glTF names a buffer it does not have");
  }
}

}  // namespace mrvol
