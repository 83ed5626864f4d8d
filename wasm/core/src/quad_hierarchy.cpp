#include "mrvol/quad_hierarchy.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

#include "mrvol/corners.h"
#include "mrvol/error.h"

namespace mrvol {

namespace {
uint64_t edgeKey(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}
std::array<uint32_t, 4> faceKey(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  std::array<uint32_t, 4> k{a, b, c, d};
  std::sort(k.begin(), k.end());
  return k;
}
}  // namespace

std::vector<uint32_t> triangulateQuads(const std::vector<uint32_t>& quads) {
  std::vector<uint32_t> t;
  t.reserve(quads.size() / 4 * 6);
  for (size_t q = 0; q + 3 < quads.size(); q += 4) {
    const uint32_t a = quads[q], b = quads[q + 1], c = quads[q + 2], d = quads[q + 3];
    t.insert(t.end(), {a, b, c, a, c, d});
  }
  return t;
}

MeshTopology validateQuadMesh(const QuadMesh& mesh) {
  const size_t V = mesh.vertexCount();
  if (mesh.positions.size() % 3) throw Error("positions must hold 3 coordinates per vertex");
  if (mesh.quads.size() % 4) throw Error("quads must hold 4 vertex indices per face");
  if (mesh.quads.empty()) throw Error("the mesh has no quads");
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    if (!std::isfinite(mesh.positions[i])) throw Error("vertex " + std::to_string(i / 3) + " has a non-finite coordinate");
  std::vector<uint8_t> used(V, 0);
  std::unordered_map<uint64_t, uint32_t> directed;  // (a -> b) -> quad
  directed.reserve(mesh.quads.size());
  for (size_t q = 0; q < mesh.faceCount(); ++q) {
    const uint32_t* c = &mesh.quads[4 * q];
    for (int i = 0; i < 4; ++i) {
      if (c[i] >= V)
        throw Error("quad " + std::to_string(q) + " refers to vertex " + std::to_string(c[i]) + " but the mesh has " +
                    std::to_string(V) + " vertices");
      used[c[i]] = 1;
      for (int j = 0; j < i; ++j)
        if (c[i] == c[j]) throw Error("quad " + std::to_string(q) + " is degenerate (vertex " + std::to_string(c[i]) + " twice)");
    }
    for (int i = 0; i < 4; ++i) {
      const uint32_t a = c[i], b = c[(i + 1) % 4];
      auto [it, fresh] = directed.emplace((uint64_t(a) << 32) | b, uint32_t(q));
      if (!fresh)
        throw Error("edge " + std::to_string(a) + "-" + std::to_string(b) + " is used in the same direction by quads " +
                    std::to_string(it->second) + " and " + std::to_string(q) +
                    " (inconsistent orientation or a non-manifold edge)");
    }
  }
  for (size_t v = 0; v < V; ++v)
    if (!used[v]) throw Error("vertex " + std::to_string(v) + " is used by no quad");
  // Vertex manifoldness and the topology: the triangle checks on the triangulation (the diagonals
  // are new edges that can only be shared within their quad).
  TriangleMesh t;
  t.positions = mesh.positions;
  t.faces = triangulateQuads(mesh.quads);
  try {
    MeshTopology topo = validateMesh(t);
    topo.edges = (directed.size() + topo.boundaryEdges) / 2;  // the quads' edges, not the diagonals
    return topo;
  } catch (const Error& e) {
    throw Error(std::string("quad mesh (triangle f is in quad f / 2): ") + e.what());
  }
}

// ---------------------------------------------------------------------------------------------

QuadHierarchy QuadHierarchy::subdivide(const std::vector<uint32_t>& baseQuads, uint32_t baseVertexCount, int levels) {
  if (levels < 0) throw Error("the number of levels must be at least 0");
  QuadHierarchy q;
  Hierarchy& h = q.h;
  h.levels = levels;
  h.vertexCount = {baseVertexCount};
  q.quads = {baseQuads};
  h.ends.assign(2 * size_t(baseVertexCount), kNone);
  for (int l = 1; l <= levels; ++l) {
    const std::vector<uint32_t>& coarse = q.quads[l - 1];
    const uint32_t V = h.vertexCount[l - 1];
    const uint32_t F = uint32_t(coarse.size() / 4);
    const uint64_t fineCount = uint64_t(V) + F + (coarse.size() + 0);  // upper bound: V + F + 4F edges
    if (fineCount >= (uint64_t(1) << 32)) throw Error("too many vertices after " + std::to_string(l) + " splits");
    QuadSplit split;
    split.facePoint.resize(F);
    for (uint32_t f = 0; f < F; ++f) split.facePoint[f] = V + f;
    uint32_t next = V + F;
    std::unordered_map<uint64_t, uint32_t> edgeIndex;
    edgeIndex.reserve(coarse.size());
    std::vector<uint32_t> edgeOf(coarse.size());
    for (uint32_t f = 0; f < F; ++f)
      for (int i = 0; i < 4; ++i) {
        const uint32_t a = coarse[4 * f + i], b = coarse[4 * f + (i + 1) % 4];
        auto [it, fresh] = edgeIndex.emplace(edgeKey(a, b), uint32_t(split.edges.size()));
        if (fresh) {
          split.edges.push_back({a, b, next++, V + f, kNone});
        } else {
          QuadSplit::Edge& e = split.edges[it->second];
          if (e.face1 != kNone) throw Error("edge " + std::to_string(a) + "-" + std::to_string(b) + " has more than two quads");
          e.face1 = V + f;
        }
        edgeOf[4 * f + i] = it->second;
      }
    h.vertexCount.push_back(next);
    h.ends.resize(2 * size_t(next), kNone);
    for (const auto& e : split.edges) h.ends[2 * size_t(e.point)] = e.a, h.ends[2 * size_t(e.point) + 1] = e.b;
    std::vector<uint32_t> fine;
    fine.reserve(4 * coarse.size());
    for (uint32_t f = 0; f < F; ++f)
      for (int i = 0; i < 4; ++i) {
        const uint32_t corner = coarse[4 * f + i];
        const uint32_t after = split.edges[edgeOf[4 * f + i]].point;
        const uint32_t before = split.edges[edgeOf[4 * f + (i + 3) % 4]].point;
        fine.insert(fine.end(), {corner, after, split.facePoint[f], before});
      }
    q.quads.push_back(std::move(fine));
    q.splits.push_back(std::move(split));
  }
  const uint32_t N = h.vertexCount.back();
  h.wings.assign(2 * size_t(N), kNone);
  h.inputIndex.resize(N);
  std::iota(h.inputIndex.begin(), h.inputIndex.end(), 0u);
  h.hierarchyIndex = h.inputIndex;
  for (const auto& quads : q.quads) h.faces.push_back(triangulateQuads(quads));
  // Boundary: the ends of fine edges used by one quad.
  h.boundary.assign(N, 0);
  std::unordered_map<uint64_t, uint32_t> uses;
  const auto& fq = q.quads.back();
  uses.reserve(fq.size());
  for (size_t f = 0; f < fq.size(); f += 4)
    for (int i = 0; i < 4; ++i) ++uses[edgeKey(fq[f + i], fq[f + (i + 1) % 4])];
  for (auto& [key, count] : uses)
    if (count == 1) h.boundary[uint32_t(key >> 32)] = h.boundary[uint32_t(key & 0xffffffffu)] = 1;
  return q;
}

// ---------------------------------------------------------------------------------------------
// Detection. In a split mesh every fine quad has one old vertex (V), its face point (F) at the
// opposite corner, and two edge points (E): the corners read V, E, F, E around it. Labelling one
// quad fixes its neighbours through its V and F corners; per component, the four ways to label a
// seed quad are tried.

namespace {

enum Label : uint8_t { kUnknown = 0, kOld = 1, kFace = 2, kEdge = 3 };

struct DetectedSplit {
  std::vector<uint32_t> coarseToFine;   // coarse vertex -> fine vertex
  std::vector<uint32_t> coarseQuads;    // coarse numbering
  std::vector<uint32_t> facePointOf;    // per coarse quad: fine vertex
  std::map<uint64_t, uint32_t> edgePointOf;  // coarse edge key (coarse numbering) -> fine vertex
};

bool detectSplit(const std::vector<uint32_t>& quads, uint32_t V, DetectedSplit& out) {
  const uint32_t F = uint32_t(quads.size() / 4);
  if (F == 0 || F % 4) return false;
  // Corners of each vertex: (quad, corner index).
  std::vector<uint32_t> start(V + 1, 0), corner(quads.size());
  for (uint32_t v : quads) ++start[v + 1];
  for (uint32_t v = 0; v < V; ++v) start[v + 1] += start[v];
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t c = 0; c < quads.size(); ++c) corner[fill[quads[c]]++] = c;
  }
  std::vector<uint8_t> label(V, kUnknown), quadDone(F, 0);
  std::vector<uint32_t> touchedV, touchedQ, queue;
  auto labelQuad = [&](uint32_t q, int oldCorner) {
    static constexpr uint8_t pattern[4] = {kOld, kEdge, kFace, kEdge};
    for (int i = 0; i < 4; ++i) {
      const uint32_t v = quads[4 * q + i];
      const uint8_t want = pattern[(i - oldCorner + 4) % 4];
      if (label[v] == kUnknown) label[v] = want, touchedV.push_back(v);
      else if (label[v] != want) return false;
    }
    quadDone[q] = 1;
    touchedQ.push_back(q);
    queue.push_back(q);
    return true;
  };
  auto labelComponent = [&](uint32_t seed, int oldCorner) {
    queue.clear();
    if (!labelQuad(seed, oldCorner)) return false;
    for (size_t head = 0; head < queue.size(); ++head) {
      const uint32_t q = queue[head];
      for (int i = 0; i < 4; ++i) {
        const uint32_t v = quads[4 * q + i];
        if (label[v] == kEdge) continue;
        for (uint32_t k = start[v]; k < start[v + 1]; ++k) {
          const uint32_t c = corner[k], q2 = c / 4;
          const int at = int(c % 4);
          if (quadDone[q2]) {
            // Consistency: v keeps its label in q2 (checked when q2 was labelled, but v may be newer).
            const uint8_t lv = label[v];
            const uint32_t opp = quads[4 * q2 + (at + 2) % 4];
            if (label[opp] != (lv == kOld ? kFace : kOld)) return false;
            continue;
          }
          if (!labelQuad(q2, label[v] == kOld ? at : (at + 2) % 4)) return false;
        }
      }
    }
    // Face points: four quads, a closed fan; edge points: two or four quads.
    for (uint32_t v : touchedV) {
      const uint32_t count = start[v + 1] - start[v];
      if (label[v] == kFace && count != 4) return false;
      if (label[v] == kEdge && count != 2 && count != 4) return false;
    }
    return true;
  };
  for (uint32_t seed = 0; seed < F; ++seed) {
    if (quadDone[seed]) continue;
    bool ok = false;
    for (int k = 0; k < 4 && !ok; ++k) {
      touchedV.clear(), touchedQ.clear();
      ok = labelComponent(seed, k);
      if (!ok) {
        for (uint32_t v : touchedV) label[v] = kUnknown;
        for (uint32_t q : touchedQ) quadDone[q] = 0;
      }
    }
    if (!ok) return false;
  }
  // Coarse vertices in fine order.
  std::vector<uint32_t> coarseOf(V, kNone);
  out.coarseToFine.clear();
  for (uint32_t v = 0; v < V; ++v)
    if (label[v] == kOld) coarseOf[v] = uint32_t(out.coarseToFine.size()), out.coarseToFine.push_back(v);
  // Coarse quads around each face point: the quad (f, e_next, v, e_prev) is followed by the one
  // whose e_next is this one's e_prev.
  out.coarseQuads.clear();
  out.facePointOf.clear();
  std::vector<uint8_t> used(F, 0);
  for (uint32_t f = 0; f < V; ++f) {
    if (label[f] != kFace) continue;
    uint32_t fan[4], at[4];
    for (int i = 0; i < 4; ++i) fan[i] = corner[start[f] + i] / 4, at[i] = corner[start[f] + i] % 4;
    uint32_t cur = 0;
    uint32_t coarse[4];
    for (int step = 0; step < 4; ++step) {
      const uint32_t q = fan[cur];
      if (used[q]) return false;
      used[q] = 1;
      coarse[step] = coarseOf[quads[4 * q + (at[cur] + 2) % 4]];
      const uint32_t ePrev = quads[4 * q + (at[cur] + 3) % 4];
      uint32_t nextI = 4;
      for (uint32_t i = 0; i < 4; ++i)
        if (quads[4 * fan[i] + (at[i] + 1) % 4] == ePrev) nextI = i;
      if (nextI == 4) return false;
      cur = nextI;
    }
    if (cur != 0) return false;
    out.coarseQuads.insert(out.coarseQuads.end(), coarse, coarse + 4);
    out.facePointOf.push_back(f);
  }
  if (out.coarseQuads.size() != size_t(F)) return false;  // F / 4 coarse quads, 4 indices each
  // Edge points: exactly two old neighbours, which must be the ends of a coarse edge.
  out.edgePointOf.clear();
  size_t edgePoints = 0;
  for (uint32_t e = 0; e < V; ++e) {
    if (label[e] != kEdge) continue;
    ++edgePoints;
    uint32_t ends[2] = {kNone, kNone};
    int n = 0;
    for (uint32_t k = start[e]; k < start[e + 1]; ++k) {
      const uint32_t c = corner[k], q = c / 4, i = c % 4;
      for (uint32_t w : {quads[4 * q + (i + 1) % 4], quads[4 * q + (i + 3) % 4]}) {
        if (label[w] != kOld || w == ends[0] || w == ends[1]) continue;
        if (n == 2) return false;
        ends[n++] = w;
      }
    }
    if (n != 2) return false;
    if (!out.edgePointOf.emplace(edgeKey(coarseOf[ends[0]], coarseOf[ends[1]]), e).second) return false;
  }
  std::vector<uint64_t> coarseEdges;
  for (size_t q = 0; q < out.coarseQuads.size(); q += 4)
    for (int i = 0; i < 4; ++i) coarseEdges.push_back(edgeKey(out.coarseQuads[q + i], out.coarseQuads[q + (i + 1) % 4]));
  std::sort(coarseEdges.begin(), coarseEdges.end());
  coarseEdges.erase(std::unique(coarseEdges.begin(), coarseEdges.end()), coarseEdges.end());
  if (coarseEdges.size() != edgePoints) return false;
  for (uint64_t k : coarseEdges)
    if (!out.edgePointOf.count(k)) return false;
  if (out.coarseToFine.size() + out.facePointOf.size() + edgePoints != V) return false;
  // The coarse mesh must itself be a valid quad mesh.
  QuadMesh coarse;
  coarse.positions.assign(3 * out.coarseToFine.size(), 0.0);
  coarse.quads = out.coarseQuads;
  try {
    validateQuadMesh(coarse);
  } catch (const Error&) {
    return false;
  }
  return true;
}

}  // namespace

QuadHierarchy QuadHierarchy::detect(const QuadMesh& fine, int maxLevels) {
  validateQuadMesh(fine);
  const uint32_t N = uint32_t(fine.vertexCount());
  // Bottom-up: each detected split, with its vertices traced back to the caller's.
  std::vector<uint32_t> quads = fine.quads;
  std::vector<uint32_t> toInput(N);
  std::iota(toInput.begin(), toInput.end(), 0u);
  // Per detected level (finest first): face points and edge points keyed by input indices.
  std::vector<std::map<std::array<uint32_t, 4>, uint32_t>> facePoints;
  std::vector<std::unordered_map<uint64_t, uint32_t>> edgePoints;
  while (int(facePoints.size()) < maxLevels) {
    DetectedSplit s;
    if (!detectSplit(quads, uint32_t(toInput.size()), s)) break;
    std::vector<uint32_t> coarseInput(s.coarseToFine.size());
    for (size_t c = 0; c < coarseInput.size(); ++c) coarseInput[c] = toInput[s.coarseToFine[c]];
    std::map<std::array<uint32_t, 4>, uint32_t> fp;
    for (size_t q = 0; q < s.facePointOf.size(); ++q) {
      const uint32_t* c = &s.coarseQuads[4 * q];
      fp[faceKey(coarseInput[c[0]], coarseInput[c[1]], coarseInput[c[2]], coarseInput[c[3]])] = toInput[s.facePointOf[q]];
    }
    std::unordered_map<uint64_t, uint32_t> ep;
    for (auto& [key, e] : s.edgePointOf)
      ep[edgeKey(coarseInput[uint32_t(key >> 32)], coarseInput[uint32_t(key & 0xffffffffu)])] = toInput[e];
    facePoints.push_back(std::move(fp));
    edgePoints.push_back(std::move(ep));
    quads = std::move(s.coarseQuads);
    toInput = std::move(coarseInput);
  }
  const int levels = int(facePoints.size());
  // Base vertices in ascending caller order.
  std::vector<uint32_t> order(toInput.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return toInput[a] < toInput[b]; });
  std::vector<uint32_t> rank(order.size());
  for (uint32_t i = 0; i < order.size(); ++i) rank[order[i]] = i;
  for (uint32_t& v : quads) v = rank[v];
  QuadHierarchy q = subdivide(quads, uint32_t(toInput.size()), levels);
  Hierarchy& h = q.h;
  std::vector<uint32_t> input(h.fineVertexCount(), kNone);
  for (uint32_t i = 0; i < order.size(); ++i) input[i] = toInput[order[i]];
  for (int l = 1; l <= levels; ++l) {
    const auto& fp = facePoints[levels - l];
    const auto& ep = edgePoints[levels - l];
    const auto& coarse = q.quads[l - 1];
    const QuadSplit& split = q.splits[l - 1];
    for (size_t f = 0; f < split.facePoint.size(); ++f) {
      auto it = fp.find(faceKey(input[coarse[4 * f]], input[coarse[4 * f + 1]], input[coarse[4 * f + 2]], input[coarse[4 * f + 3]]));
      if (it == fp.end()) throw Error("quad hierarchy detection is inconsistent (face point)");
      input[split.facePoint[f]] = it->second;
    }
    for (const auto& e : split.edges) {
      auto it = ep.find(edgeKey(input[e.a], input[e.b]));
      if (it == ep.end()) throw Error("quad hierarchy detection is inconsistent (edge point)");
      input[e.point] = it->second;
    }
  }
  h.inputIndex = input;
  h.hierarchyIndex.assign(N, kNone);
  for (uint32_t i = 0; i < N; ++i) {
    if (input[i] >= N || h.hierarchyIndex[input[i]] != kNone) throw Error("quad hierarchy detection is inconsistent (numbering)");
    h.hierarchyIndex[input[i]] = i;
  }
  // The fine quads, mapped back, must be the caller's (each up to rotation).
  auto canonical = [](std::vector<uint32_t> qs) {
    std::vector<std::array<uint32_t, 4>> out;
    for (size_t f = 0; f < qs.size(); f += 4) {
      int m = int(std::min_element(qs.begin() + f, qs.begin() + f + 4) - (qs.begin() + f));
      out.push_back({qs[f + m], qs[f + (m + 1) % 4], qs[f + (m + 2) % 4], qs[f + (m + 3) % 4]});
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  std::vector<uint32_t> mapped = q.quads.back();
  for (uint32_t& v : mapped) v = input[v];
  if (canonical(mapped) != canonical(fine.quads)) throw Error("quad hierarchy detection is inconsistent (quads)");
  return q;
}

}  // namespace mrvol
