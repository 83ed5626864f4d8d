#include "mrvol/hierarchy.h"

#include <algorithm>
#include <numeric>
#include <string>

#include "mrvol/corners.h"
#include "mrvol/error.h"

namespace mrvol {

int Hierarchy::depth(uint32_t v) const {
  int l = 0;
  while (v >= vertexCount[l]) ++l;
  return l;
}

bool Hierarchy::closed() const {
  return std::find(boundary.begin(), boundary.end(), 1) == boundary.end();
}

void Hierarchy::toHierarchyOrder(const double* input, double* out) const {
  for (size_t h = 0; h < inputIndex.size(); ++h)
    for (int k = 0; k < 3; ++k) out[3 * h + k] = input[3 * size_t(inputIndex[h]) + k];
}

void Hierarchy::toInputOrder(const double* ordered, double* out) const {
  for (size_t h = 0; h < inputIndex.size(); ++h)
    for (int k = 0; k < 3; ++k) out[3 * size_t(inputIndex[h]) + k] = ordered[3 * h + k];
}

namespace {

// Wings of the odd vertices and boundary flags, from the level faces and the ends. `wingsKnown`:
// h.wings already holds them (detection finds them in its tiling walk, without corner lists);
// only the order of a boundary edge's ends and wings is settled here.
void finish(Hierarchy& h, bool wingsKnown = false) {
  const size_t n = h.fineVertexCount();
  if (wingsKnown) {
    for (uint32_t e = h.vertexCount[0]; e < n; ++e)
      if (h.wings[2 * e] == kNone) {  // keep the existing wing first
        std::swap(h.ends[2 * e], h.ends[2 * e + 1]);
        std::swap(h.wings[2 * e], h.wings[2 * e + 1]);
      }
  } else {
    h.wings.assign(2 * n, kNone);
  }
  for (int l = 1; l <= h.levels && !wingsKnown; ++l) {
    const auto& coarse = h.faces[l - 1];
    VertexCorners corners(coarse.data(), coarse.size() / 3, h.vertexCount[l - 1]);
    for (uint32_t e = h.vertexCount[l - 1]; e < h.vertexCount[l]; ++e) {
      uint32_t a = h.ends[2 * e], b = h.ends[2 * e + 1];
      h.wings[2 * e] = corners.opposite(a, b);
      h.wings[2 * e + 1] = corners.opposite(b, a);
      if (h.wings[2 * e] == kNone) {  // keep the existing wing first
        std::swap(h.ends[2 * e], h.ends[2 * e + 1]);
        std::swap(h.wings[2 * e], h.wings[2 * e + 1]);
      }
    }
  }
  h.boundary.assign(n, 0);
  // Splits keep a closed base closed: then no fine vertex is on the boundary, and the fine corner
  // lists (the largest) need not be built again.
  if (h.levels >= 1) {
    const auto& base = h.faces[0];
    VertexCorners baseCorners(base.data(), base.size() / 3, h.vertexCount[0]);
    bool closed = true;
    for (uint32_t u = 0; u < h.vertexCount[0] && closed; ++u)
      for (uint32_t c = baseCorners.begin(u); c < baseCorners.end(u) && closed; ++c)
        closed = baseCorners.opposite(baseCorners.next[c], u) != kNone;
    if (closed) return;
  }
  const auto& fine = h.fineFaces();
  VertexCorners corners(fine.data(), fine.size() / 3, n);
  for (uint32_t u = 0; u < n; ++u)
    for (uint32_t c = corners.begin(u); c < corners.end(u); ++c)
      if (corners.opposite(corners.next[c], u) == kNone) h.boundary[u] = h.boundary[corners.next[c]] = 1;
}

// One 1-to-4 split of faces on [0, vertexCount): new vertices numbered from vertexCount on.
// Returns the new faces; appends the ends of each new vertex.
std::vector<uint32_t> splitOnce(const std::vector<uint32_t>& faces, uint32_t vertexCount, std::vector<uint32_t>& ends) {
  const size_t nf = faces.size() / 3;
  VertexCorners corners(faces.data(), nf, vertexCount);
  std::vector<uint32_t> cornerOdd(corners.next.size(), kNone);
  std::vector<uint32_t> faceEdgeOdd(3 * nf, kNone);  // odd vertex on edge faces[3f+k] -> faces[3f+k+1]
  uint32_t next = vertexCount;
  for (uint32_t u = 0; u < vertexCount; ++u)
    for (uint32_t c = corners.begin(u); c < corners.end(u); ++c) {
      if (cornerOdd[c] == kNone) {
        uint32_t v = corners.next[c];
        cornerOdd[c] = next;
        const uint32_t d = corners.cornerTo(v, u);  // the other side of the edge, if any
        if (d != kNone) cornerOdd[d] = next;
        ends.push_back(u);
        ends.push_back(v);
        ++next;
      }
      uint32_t f = corners.face[c];
      int k = faces[3 * f] == u ? 0 : faces[3 * f + 1] == u ? 1 : 2;
      faceEdgeOdd[3 * f + k] = cornerOdd[c];
    }
  std::vector<uint32_t> out;
  out.reserve(12 * nf);
  for (size_t f = 0; f < nf; ++f) {
    uint32_t a = faces[3 * f], b = faces[3 * f + 1], c = faces[3 * f + 2];
    uint32_t ab = faceEdgeOdd[3 * f], bc = faceEdgeOdd[3 * f + 1], ca = faceEdgeOdd[3 * f + 2];
    uint32_t t[12] = {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca};
    out.insert(out.end(), t, t + 12);
  }
  return out;
}

}  // namespace

Hierarchy Hierarchy::subdivide(const TriangleMesh& base, int levels) {
  if (levels < 0 || levels > 12) throw Error("levels must be between 0 and 12, got " + std::to_string(levels));
  Hierarchy h;
  h.levels = levels;
  h.vertexCount.push_back(uint32_t(base.vertexCount()));
  h.faces.push_back(base.faces);
  h.ends.assign(2 * base.vertexCount(), kNone);
  for (int l = 1; l <= levels; ++l) {
    uint64_t estimate = uint64_t(h.vertexCount.back()) + h.faces.back().size() / 2;
    if (estimate > 50'000'000)
      throw Error("subdividing " + std::to_string(levels) + " times would make more than 50 million vertices");
    h.faces.push_back(splitOnce(h.faces.back(), h.vertexCount.back(), h.ends));
    h.vertexCount.push_back(uint32_t(h.ends.size() / 2));
  }
  h.inputIndex.resize(h.fineVertexCount());
  std::iota(h.inputIndex.begin(), h.inputIndex.end(), 0u);
  h.hierarchyIndex = h.inputIndex;
  finish(h);
  return h;
}

namespace {

enum Role : uint8_t { kUnknown = 0, kEven = 1, kOdd = 2 };

// One level of quadrisection detection on a validated mesh. On success fills the coarse faces (in
// the same vertex indices), the role of every vertex and the ends of every odd vertex.
struct Quadrisection {
  std::vector<uint32_t> coarseFaces;
  std::vector<uint8_t> role;
  std::vector<uint32_t> ends;  // 2 per vertex, the lower index first
  // 2 per vertex: w with the coarse face (ends[0], ends[1], w), then with (ends[1], ends[0], w)
  std::vector<uint32_t> wings;
  VertexCorners coarseCorners;  // of the coarse faces in the even vertices' compact numbering
};

// `corners`: the corner lists of `faces` (built once per level: the coarse level's come from its
// validation here and serve the next level's detection).
bool tryDetect(const std::vector<uint32_t>& faces, uint32_t vertexCount, const VertexCorners& corners,
               Quadrisection& out) {
  const size_t nf = faces.size() / 3;
  if (nf % 4 != 0 || nf == 0) return false;
  auto faceOf = [&](uint32_t u, uint32_t v) -> uint32_t {  // face (u, v, .)
    const uint32_t c = corners.cornerTo(u, v);
    return c == kNone ? kNone : corners.face[c];
  };
  std::vector<uint8_t> role(vertexCount, kUnknown);
  std::vector<uint32_t> ends(2 * size_t(vertexCount), kNone);
  std::vector<uint32_t> tileOfFace(nf, kNone);
  std::vector<uint8_t> isCenter(nf, 0);
  std::vector<uint32_t> coarse;
  volatile uint32_t warmSink = 0;  // keeps the cache-warming loads below from being optimised away
  coarse.reserve(3 * (nf / 4));  // exact for a split: no growth by reallocation on a large mesh
  std::vector<uint32_t> centreOfTile;  // the fine face at the centre of each coarse face
  centreOfTile.reserve(nf / 4);

  // Grows the tiling of one component from a face taken as a tile's centre. Undo on failure.
  auto grow = [&](uint32_t seed) -> bool {
    std::vector<uint32_t> queue{seed}, touchedVertices, touchedFaces;
    size_t coarseBefore = coarse.size();
    auto setRole = [&](uint32_t v, Role r) {
      if (role[v] == r) return true;
      if (role[v] != kUnknown) return false;
      role[v] = r;
      touchedVertices.push_back(v);
      return true;
    };
    auto claim = [&](uint32_t f, uint32_t tile) {
      if (f == kNone || tileOfFace[f] != kNone) return false;
      tileOfFace[f] = tile;
      touchedFaces.push_back(f);
      return true;
    };
    bool ok = true;
    isCenter[seed] = 1;
    touchedFaces.push_back(seed);
    // The walk's faces are scattered in memory: the next queued faces' vertices are gathered a
    // batch at a time, loads that do not wait on each other (the walk itself is one long chain of
    // dependent ones). The same faces in the same order: only when they are read changes.
    constexpr size_t kBatch = 32;
    uint32_t batch[3 * kBatch];
    size_t batchStart = 0, batchEnd = 0;
    for (size_t qi = 0; qi < queue.size() && ok; ++qi) {
      if (qi == batchEnd) {
        batchStart = qi;
        batchEnd = std::min(queue.size(), qi + kBatch);
        const size_t n = 3 * (batchEnd - batchStart);
        for (size_t i = batchStart; i < batchEnd; ++i)
          for (int k = 0; k < 3; ++k) batch[3 * (i - batchStart) + k] = faces[3 * size_t(queue[i]) + k];
        // Then what the walk reads of those vertices (their corners, their ends), in two waves of
        // independent loads, so that the walk finds them in the cache.
        uint32_t touched = 0;
        for (size_t i = 0; i < n; ++i) touched ^= corners.offset[batch[i]] ^ ends[2 * size_t(batch[i])];
        for (size_t i = 0; i < n; ++i) {
          const uint32_t c = corners.offset[batch[i]];
          touched ^= corners.next[c] ^ corners.prev[c] ^ corners.face[c];
        }
        warmSink = touched;
      }
      const uint32_t f = queue[qi];
      const uint32_t* pqr = batch + 3 * (qi - batchStart);
      const uint32_t p = pqr[0], q = pqr[1], r = pqr[2];
      // Centre (p, q, r) = (ab, bc, ca) of coarse triangle (a, b, c).
      uint32_t a = corners.opposite(p, r), b = corners.opposite(q, p), c = corners.opposite(r, q);
      if (a == kNone || b == kNone || c == kNone || a == b || b == c || a == c) { ok = false; break; }
      uint32_t tile = uint32_t(coarse.size() / 3);
      if (!claim(f, tile) || !claim(faceOf(p, r), tile) || !claim(faceOf(q, p), tile) || !claim(faceOf(r, q), tile)) {
        ok = false;
        break;
      }
      coarse.insert(coarse.end(), {a, b, c});
      centreOfTile.push_back(f);
      const uint32_t mids[3] = {p, q, r}, from[3] = {a, b, c}, to[3] = {b, c, a};
      for (int k = 0; k < 3 && ok; ++k) {
        uint32_t m = mids[k];
        ok = setRole(from[k], kEven) && setRole(m, kOdd);
        if (!ok) break;
        uint32_t lo = std::min(from[k], to[k]), hi = std::max(from[k], to[k]);
        if (ends[2 * m] == kNone) ends[2 * m] = lo, ends[2 * m + 1] = hi;
        else if (ends[2 * m] != lo || ends[2 * m + 1] != hi) { ok = false; break; }
        // The neighbouring tile's centre is three faces further around m.
        uint32_t x = mids[(k + 1) % 3], y = mids[(k + 2) % 3];  // centre seen from m: (m, x, y)
        (void)x;
        uint32_t v = y, steps = 0, g = kNone;
        for (; steps < 3; ++steps) {
          uint32_t w = corners.opposite(m, v);
          if (w == kNone) break;
          if (steps == 2) g = faceOf(m, v);
          v = w;
        }
        if (g == kNone) continue;  // boundary edge of the coarse mesh
        if (!isCenter[g]) {
          if (tileOfFace[g] != kNone) { ok = false; break; }
          isCenter[g] = 1;
          touchedFaces.push_back(g);
          queue.push_back(g);
        }
      }
    }
    if (!ok) {
      for (uint32_t v : touchedVertices)
        role[v] = kUnknown, ends[2 * v] = ends[2 * v + 1] = kNone;
      for (uint32_t f : touchedFaces) tileOfFace[f] = kNone, isCenter[f] = 0;
      // Ends may have been set on vertices whose role was set by an earlier component: none, since
      // components share no vertices.
      coarse.resize(coarseBefore);
      centreOfTile.resize(coarseBefore / 3);
    }
    return ok;
  };

  for (uint32_t f0 = 0; f0 < nf; ++f0) {
    if (tileOfFace[f0] != kNone) continue;
    // One of f0 and its three edge neighbours is the centre of its tile.
    uint32_t candidates[4] = {f0, kNone, kNone, kNone};
    for (int k = 0; k < 3; ++k) candidates[k + 1] = faceOf(faces[3 * f0 + (k + 1) % 3], faces[3 * f0 + k]);
    bool grown = false;
    for (uint32_t s : candidates)
      if (s != kNone && tileOfFace[s] == kNone && grow(s)) { grown = true; break; }
    if (!grown) return false;
  }
  // The tiling's own arrays are done with: freed before the checks' arrays are made.
  std::vector<uint32_t>().swap(tileOfFace);
  std::vector<uint8_t>().swap(isCenter);
  // Wings: the midpoint of each edge (from, to) of a coarse face (from, to, third) has the wing
  // third on that side (made here, after the tiling's arrays are freed: a smaller peak).
  std::vector<uint32_t> wings(2 * size_t(vertexCount), kNone);
  for (size_t t = 0; t < centreOfTile.size(); ++t) {
    const uint32_t* mids = &faces[3 * size_t(centreOfTile[t])];  // (ab, bc, ca) of (a, b, c)
    const uint32_t* abc = &coarse[3 * t];
    for (int k = 0; k < 3; ++k) {
      const uint32_t from = abc[k], to = abc[(k + 1) % 3];
      wings[2 * size_t(mids[k]) + (from < to ? 0 : 1)] = abc[(k + 2) % 3];
    }
  }
  std::vector<uint32_t>().swap(centreOfTile);
  size_t evens = 0, odds = 0;
  for (uint32_t v = 0; v < vertexCount; ++v) {
    if (role[v] == kUnknown) return false;
    (role[v] == kEven ? evens : odds)++;
  }
  // Counts of a 1-to-4 split: 4 F_coarse = F_fine, V_coarse + E_coarse = V_fine.
  if (4 * (coarse.size() / 3) != nf || evens + odds != vertexCount) return false;
  // The coarse mesh must be a valid manifold with interior valence >= 3 (no pillow of two faces).
  std::vector<uint32_t> evenIndex(vertexCount, kNone);
  uint32_t ne = 0;
  for (uint32_t v = 0; v < vertexCount; ++v)
    if (role[v] == kEven) evenIndex[v] = ne++;
  TriangleMesh coarseMesh;
  coarseMesh.positions.assign(3 * size_t(ne), 0.0);
  coarseMesh.faces.resize(coarse.size());
  for (size_t i = 0; i < coarse.size(); ++i) coarseMesh.faces[i] = evenIndex[coarse[i]];
  std::vector<uint32_t>().swap(evenIndex);
  VertexCorners coarseCorners;
  MeshTopology coarseTopology;
  try {
    coarseTopology = validateMesh(coarseMesh, nullptr, &coarseCorners);
  } catch (const Error&) {
    return false;
  }
  // Each coarse edge has one midpoint: every edge of a tile's coarse face has one (the walk set its
  // ends), so the odd vertices cover the coarse edges, once each exactly when they are as many.
  if (coarseTopology.edges != odds) return false;
  // An interior vertex's ring has as many vertices as it has corners: only a vertex of fewer than
  // three corners needs its ring walked (to tell whether it is on the boundary).
  std::vector<uint32_t> ring;
  for (uint32_t v = 0; v < ne; ++v) {
    if (coarseCorners.count(v) >= 3) continue;
    bool isBoundary = false;
    coarseCorners.ring(v, ring, &isBoundary);
    if (!isBoundary && ring.size() < 3) return false;
  }
  out.coarseFaces = std::move(coarse);
  out.role = std::move(role);
  out.ends = std::move(ends);
  out.wings = std::move(wings);
  out.coarseCorners = std::move(coarseCorners);
  return true;
}

}  // namespace

Hierarchy Hierarchy::detect(const TriangleMesh& fine, int maxLevels, bool validated) {
  VertexCorners corners;
  if (!validated) validateMesh(fine, nullptr, &corners);
  return detectValidated(fine.faces, fine.vertexCount(), maxLevels, validated ? nullptr : &corners);
}

Hierarchy Hierarchy::detectValidated(const std::vector<uint32_t>& fineFaces, size_t vertexCount, int maxLevels,
                                     VertexCorners* fineCorners, const std::vector<uint32_t>* localToCaller) {
  const uint32_t nv = uint32_t(vertexCount);
  // The corner lists of the level being detected: the fine ones given or built, then each coarse
  // level's from its validation.
  VertexCorners corners;
  if (fineCorners) corners = std::move(*fineCorners);
  else if (maxLevels > 0) corners = VertexCorners(fineFaces.data(), fineFaces.size() / 3, nv);
  // Top-down: level meshes in the caller's vertex indices; depth of each vertex.
  std::vector<std::vector<uint32_t>> levelFaces{{}};  // [0]: the fine faces, read from `fine`
  // Per vertex (made once the finest level is detected and its corner lists freed: a smaller peak).
  std::vector<int> bornAt;  // levels found from the top: 0 = born at the finest level, -1 = base
  std::vector<uint32_t> endsInput, wingsInput;
  auto makePerVertex = [&] {
    if (!bornAt.empty()) return;
    bornAt.assign(nv, -1);
    endsInput.assign(2 * size_t(nv), kNone);
    wingsInput.assign(2 * size_t(nv), kNone);
  };
  std::vector<uint32_t> alive(nv);  // vertices of the current level, as caller indices
  std::iota(alive.begin(), alive.end(), 0u);
  int found = 0;
  while (found < maxLevels) {
    // Compact the current level's vertices.
    // The finest level is the caller's arrays as they are (no copy: they are the largest).
    std::vector<uint32_t> faces;
    if (found > 0) {
      std::vector<uint32_t> local(nv, kNone);
      for (uint32_t i = 0; i < alive.size(); ++i) local[alive[i]] = i;
      faces.resize(levelFaces.back().size());
      for (size_t i = 0; i < faces.size(); ++i) faces[i] = local[levelFaces.back()[i]];
    }
    Quadrisection q;
    if (!tryDetect(found > 0 ? faces : fineFaces, uint32_t(alive.size()), corners, q)) break;
    corners = std::move(q.coarseCorners);
    makePerVertex();
    std::vector<uint32_t> nextAlive;
    for (uint32_t i = 0; i < alive.size(); ++i) {
      if (q.role[i] == kEven) { nextAlive.push_back(alive[i]); continue; }
      bornAt[alive[i]] = found;
      endsInput[2 * alive[i]] = alive[q.ends[2 * i]];
      endsInput[2 * alive[i] + 1] = alive[q.ends[2 * i + 1]];
      for (int k = 0; k < 2; ++k)
        if (q.wings[2 * i + k] != kNone) wingsInput[2 * alive[i] + k] = alive[q.wings[2 * i + k]];
    }
    for (auto& v : q.coarseFaces) v = alive[v];
    levelFaces.push_back(std::move(q.coarseFaces));
    alive = std::move(nextAlive);
    ++found;
  }
  corners = VertexCorners();  // freed before the hierarchy's arrays are made
  makePerVertex();
  if (localToCaller) {
    // Back to the caller's numbering; ends as the caller's numbering orders them (lower index
    // first: detection orders each pair by index, and compaction keeps the order).
    const std::vector<uint32_t>& caller = *localToCaller;
    std::vector<int> callerBornAt(nv);
    for (uint32_t v = 0; v < nv; ++v) callerBornAt[caller[v]] = bornAt[v];
    std::vector<int>().swap(bornAt);
    std::vector<uint32_t> callerEnds(2 * size_t(nv), kNone), callerWings(2 * size_t(nv), kNone);
    auto toCaller = [&](uint32_t v) { return v == kNone ? kNone : caller[v]; };
    for (uint32_t v = 0; v < nv; ++v)
      if (endsInput[2 * v] != kNone) {
        const uint32_t a = caller[endsInput[2 * v]], b = caller[endsInput[2 * v + 1]];
        const size_t at = 2 * size_t(caller[v]);
        const int swapped = a > b;  // the wings follow their ends' order
        callerEnds[at] = std::min(a, b);
        callerEnds[at + 1] = std::max(a, b);
        callerWings[at + swapped] = toCaller(wingsInput[2 * v]);
        callerWings[at + 1 - swapped] = toCaller(wingsInput[2 * v + 1]);
      }
    std::vector<uint32_t>().swap(endsInput);
    std::vector<uint32_t>().swap(wingsInput);
    bornAt = std::move(callerBornAt);
    endsInput = std::move(callerEnds);
    wingsInput = std::move(callerWings);
    for (size_t l = 1; l < levelFaces.size(); ++l)
      for (auto& v : levelFaces[l]) v = caller[v];
  }
  Hierarchy h;
  h.levels = found;
  // Depth = levels - 1 - bornAt; base vertices have bornAt -1. Number by depth, then caller order.
  std::vector<std::vector<uint32_t>> byDepth(found + 1);
  for (uint32_t v = 0; v < nv; ++v) byDepth[bornAt[v] < 0 ? 0 : found - bornAt[v]].push_back(v);
  h.hierarchyIndex.assign(nv, kNone);
  for (int d = 0; d <= found; ++d) {
    for (uint32_t v : byDepth[d]) {
      h.hierarchyIndex[v] = uint32_t(h.inputIndex.size());
      h.inputIndex.push_back(v);
    }
    h.vertexCount.push_back(uint32_t(h.inputIndex.size()));
  }
  for (int l = 0; l < found; ++l) {
    std::vector<uint32_t> faces = std::move(levelFaces[found - l]);
    for (auto& v : faces) v = h.hierarchyIndex[v];
    h.faces.push_back(std::move(faces));
  }
  {
    // The fine faces, mapped as they are copied. In the local numbering through one composed
    // table: the faces read it nearly in order (first appearance), where caller then hierarchy
    // index would be two scattered reads per corner.
    std::vector<uint32_t> faces(fineFaces.size());
    if (localToCaller) {
      std::vector<uint32_t> localToHierarchy(nv);
      for (uint32_t v = 0; v < nv; ++v) localToHierarchy[v] = h.hierarchyIndex[(*localToCaller)[v]];
      for (size_t i = 0; i < faces.size(); ++i) faces[i] = localToHierarchy[fineFaces[i]];
    } else {
      for (size_t i = 0; i < faces.size(); ++i) faces[i] = h.hierarchyIndex[fineFaces[i]];
    }
    h.faces.push_back(std::move(faces));
  }
  h.ends.assign(2 * size_t(nv), kNone);
  h.wings.assign(2 * size_t(nv), kNone);
  for (uint32_t v = 0; v < nv; ++v)
    if (endsInput[2 * v] != kNone) {
      const size_t at = 2 * size_t(h.hierarchyIndex[v]);
      for (int k = 0; k < 2; ++k) {
        h.ends[at + k] = h.hierarchyIndex[endsInput[2 * v + k]];
        h.wings[at + k] = wingsInput[2 * v + k] == kNone ? kNone : h.hierarchyIndex[wingsInput[2 * v + k]];
      }
    }
  finish(h, true);
  return h;
}

}  // namespace mrvol
