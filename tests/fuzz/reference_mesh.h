// A second, deliberately plain implementation of the mesh rules validateMesh enforces, for
// differential fuzzing: both must accept and refuse the same meshes and agree on the counts.
// Written from the contract in mrvol/mesh.h, not from mesh.cpp: faces grouped per vertex and
// per undirected edge with std::map, fans as connected components of the faces around a vertex.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <set>
#include <utility>
#include <vector>

#include "mrvol/mesh.h"

namespace reference {

struct Topology {
  bool valid = false;
  size_t edges = 0, boundaryEdges = 0, components = 0;
};

inline uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

inline Topology validate(const mrvol::TriangleMesh& mesh) {
  Topology topo;
  if (mesh.positions.size() % 3 != 0 || mesh.faces.size() % 3 != 0) return topo;
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  if (nv == 0 || nf == 0) return topo;
  for (double x : mesh.positions)
    if (!std::isfinite(x) || std::fabs(x) > 1e100) return topo;
  std::set<std::array<uint32_t, 3>> unordered;
  std::map<std::pair<uint32_t, uint32_t>, std::vector<std::pair<uint32_t, bool>>> edgeFaces;  // face, u<v?
  std::vector<std::vector<uint32_t>> vertexFaces(nv);
  for (uint32_t f = 0; f < nf; ++f) {
    std::array<uint32_t, 3> t{mesh.faces[3 * f], mesh.faces[3 * f + 1], mesh.faces[3 * f + 2]};
    for (uint32_t v : t)
      if (v >= nv) return topo;
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return topo;
    std::array<uint32_t, 3> s = t;
    std::sort(s.begin(), s.end());
    if (!unordered.insert(s).second) return topo;  // duplicate, either orientation
    for (int k = 0; k < 3; ++k) {
      uint32_t u = t[k], v = t[(k + 1) % 3];
      edgeFaces[{std::min(u, v), std::max(u, v)}].emplace_back(f, u < v);
      vertexFaces[u].push_back(f);
    }
  }
  for (auto& [edge, faces] : edgeFaces) {
    if (faces.size() > 2) return topo;                                       // non-manifold edge
    if (faces.size() == 2 && faces[0].second == faces[1].second) return topo;  // orientation
    topo.boundaryEdges += faces.size() == 1;
  }
  topo.edges = edgeFaces.size();
  // Around each vertex: used, and its faces connected through the edges at the vertex (one fan).
  for (uint32_t u = 0; u < nv; ++u) {
    const auto& faces = vertexFaces[u];
    if (faces.empty()) return topo;
    std::map<uint32_t, std::vector<size_t>> byNeighbour;  // other end of an edge at u -> faces
    for (size_t i = 0; i < faces.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        uint32_t w = mesh.faces[3 * faces[i] + k];
        if (w != u) byNeighbour[w].push_back(i);
      }
    std::vector<uint32_t> parent(faces.size());
    std::iota(parent.begin(), parent.end(), 0u);
    for (auto& [w, list] : byNeighbour)
      for (size_t j = 1; j < list.size(); ++j) parent[findRoot(parent, uint32_t(list[0]))] = findRoot(parent, uint32_t(list[j]));
    size_t fans = 0;
    for (uint32_t i = 0; i < parent.size(); ++i) fans += findRoot(parent, i) == i;
    if (fans != 1) return topo;
  }
  std::vector<uint32_t> parent(nv);
  std::iota(parent.begin(), parent.end(), 0u);
  for (size_t f = 0; f < nf; ++f)
    for (int k = 1; k < 3; ++k) parent[findRoot(parent, mesh.faces[3 * f])] = findRoot(parent, mesh.faces[3 * f + k]);
  for (uint32_t v = 0; v < nv; ++v) topo.components += findRoot(parent, v) == v;
  topo.valid = true;
  return topo;
}

}  // namespace reference
