#include "mrvol/cage_polynomial_builder.h"

#include <algorithm>
#include <numeric>
#include <string>

#include "mrvol/corners.h"
#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/thread_pool.h"

namespace mrvol {

// A unit at each cage vertex carried through the zero-detail synthesis steps on sparse rows. A
// lift rewrites the rows of its targets (targets and sources are disjoint), merged through a dense
// accumulator over the cage; the steps that read only zero details are skipped, as in
// synthesizeZeroDetails. Rows live in a pool: vertex v's is [begin[v], begin[v] + length[v]); a
// lift appends its targets' new rows (the sources' rows stay put while it reads them) and leaves
// every other row where it is; the pool is compacted once per level, into vertex order.
namespace {

constexpr size_t kDenseRowsPerBlock = 16384;

// A small cage's rows by dense columns: units at the cage vertices [first, first + width) carried
// through the same steps, `width` doubles per vertex. Per entry the same operations in the same
// order as the sparse rows below (the target's own value, then each source's weighted value; a
// scaling multiplies), so the same bits; the exact zeros are dropped as there.
CageBasis denseCageColumns(const WaveletTransform& transform, int level, uint32_t first, uint32_t width) {
  const Hierarchy& h = transform.hierarchy();
  const size_t n = h.fineVertexCount();
  std::vector<double> x(n * width, 0.0);
  for (uint32_t c = 0; c < width; ++c) x[size_t(first + c) * width + c] = 1.0;
  for (int l = level + 1; l <= h.levels; ++l)
    for (const LiftingStep& step : transform.synthesisSteps(l)) {
      if (step.readsOnlyDetails) continue;
      if (step.scaling) {
        for (size_t r = 0; r < step.targets.size(); ++r) {
          double* xt = &x[size_t(step.targets[r]) * width];
          for (uint32_t c = 0; c < width; ++c) xt[c] *= step.weights[r];
        }
        continue;
      }
      // Targets and sources are disjoint: the rows in blocks on the pool's threads.
      // Columns four at a time in registers (a fixed width the compiler unrolls), the rest one by
      // one: per entry the same additions in the same order.
      const uint32_t wide = width & ~3u;
      parallelFor(0, step.targets.size(), kDenseRowsPerBlock, [&](size_t begin, size_t end) {
        for (size_t r = begin; r < end; ++r) {
          double* xt = &x[size_t(step.targets[r]) * width];
          const uint32_t k0 = step.offsets[r], k1 = step.offsets[r + 1];
          for (uint32_t c = 0; c < wide; c += 4) {
            double acc[4] = {xt[c], xt[c + 1], xt[c + 2], xt[c + 3]};
            for (uint32_t k = k0; k < k1; ++k) {
              const double w = step.weights[k], *xs = &x[size_t(step.sources[k]) * width + c];
              for (int q = 0; q < 4; ++q) acc[q] += w * xs[q];
            }
            for (int q = 0; q < 4; ++q) xt[c + q] = acc[q];
          }
          for (uint32_t c = wide; c < width; ++c) {
            double acc = xt[c];
            for (uint32_t k = k0; k < k1; ++k) acc += step.weights[k] * x[size_t(step.sources[k]) * width + c];
            xt[c] = acc;
          }
        }
      });
    }
  // The nonzeros by rows: a counting pass, then each row written in place (rows in blocks on the
  // pool's threads: each writes its own entries).
  CageBasis rows;
  rows.offset.assign(n + 1, 0);
  parallelFor(0, n, kDenseRowsPerBlock, [&](size_t begin, size_t end) {
    for (size_t v = begin; v < end; ++v) {
      const double* xv = &x[v * width];
      uint32_t live = 0;
      for (uint32_t c = 0; c < width; ++c) live += xv[c] != 0.0;
      rows.offset[v + 1] = live;
    }
  });
  for (size_t v = 0; v < n; ++v) rows.offset[v + 1] += rows.offset[v];
  rows.index.resize(rows.offset[n]), rows.value.resize(rows.offset[n]);
  parallelFor(0, n, kDenseRowsPerBlock, [&](size_t begin, size_t end) {
    for (size_t v = begin; v < end; ++v) {
      const double* xv = &x[v * width];
      uint64_t p = rows.offset[v];
      for (uint32_t c = 0; c < width; ++c)
        if (xv[c] != 0.0) rows.index[p] = first + c, rows.value[p++] = xv[c];
    }
  });
  return rows;
}

// The dense columns in chunks of at most denseBytes.
CageBasis denseCageBasis(const WaveletTransform& transform, int level, size_t denseBytes) {
  const Hierarchy& h = transform.hierarchy();
  const uint32_t cage = h.vertexCount[level];
  const size_t n = h.fineVertexCount();
  const uint32_t width = uint32_t(std::clamp<size_t>(denseBytes / (8 * std::max<size_t>(n, 1)), 1, cage));
  if (width == cage) return denseCageColumns(transform, level, 0, cage);
  std::vector<CageBasis> parts;
  for (uint32_t first = 0; first < cage; first += width)
    parts.push_back(denseCageColumns(transform, level, first, std::min(width, cage - first)));
  CageBasis rows;
  rows.offset.assign(n + 1, 0);
  for (size_t v = 0; v < n; ++v) {
    uint64_t length = 0;
    for (const CageBasis& part : parts) length += part.offset[v + 1] - part.offset[v];
    rows.offset[v + 1] = rows.offset[v] + length;
  }
  rows.index.reserve(rows.offset[n]), rows.value.reserve(rows.offset[n]);
  for (size_t v = 0; v < n; ++v)
    for (const CageBasis& part : parts) {  // chunks ascending: the row's indices ascending
      rows.index.insert(rows.index.end(), part.index.begin() + part.offset[v], part.index.begin() + part.offset[v + 1]);
      rows.value.insert(rows.value.end(), part.value.begin() + part.offset[v], part.value.begin() + part.offset[v + 1]);
    }
  return rows;
}

}  // namespace

CageBasis cageBasis(const WaveletTransform& transform, int level, uint32_t denseCageUpTo, size_t denseBytes) {
  const Hierarchy& h = transform.hierarchy();
  if (level < 0 || level > h.levels)
    throw Error("level " + std::to_string(level) + " is out of range: this mesh has levels 0.." + std::to_string(h.levels));
  const uint32_t cage = h.vertexCount[level];
  const size_t n = h.fineVertexCount();
  if (cage <= denseCageUpTo) return denseCageBasis(transform, level, denseBytes);
  std::vector<uint64_t> begin(n, 0);
  std::vector<uint32_t> length(n, 0);
  CageBasis rows;
  rows.index.resize(cage);
  std::iota(rows.index.begin(), rows.index.end(), 0u);
  rows.value.assign(cage, 1.0);
  for (uint32_t c = 0; c < cage; ++c) begin[c] = c, length[c] = 1;
  std::vector<double> acc(cage, 0.0);
  std::vector<uint8_t> touched(cage, 0);
  std::vector<uint32_t> list;
  std::vector<uint32_t> compactIndex;
  std::vector<double> compactValue;
  for (int l = level + 1; l <= h.levels; ++l) {
    for (const LiftingStep& step : transform.synthesisSteps(l)) {
      if (step.readsOnlyDetails) continue;
      if (step.scaling) {
        for (size_t r = 0; r < step.targets.size(); ++r) {
          const uint32_t t = step.targets[r];
          for (uint64_t p = begin[t]; p < begin[t] + length[t]; ++p) rows.value[p] *= step.weights[r];
        }
        continue;
      }
      {  // room for the new rows at once (each at most its inputs' lengths, at most the cage)
        uint64_t bound = 0;
        for (size_t r = 0; r < step.targets.size(); ++r) {
          uint64_t m = length[step.targets[r]];
          for (uint32_t k = step.offsets[r]; k < step.offsets[r + 1]; ++k) m += length[step.sources[k]];
          bound += std::min<uint64_t>(m, cage);
        }
        rows.index.reserve(rows.index.size() + bound), rows.value.reserve(rows.value.size() + bound);
      }
      for (size_t r = 0; r < step.targets.size(); ++r) {
        const uint32_t t = step.targets[r];
        const auto add = [&](uint32_t from, double w) {
          for (uint64_t p = begin[from], end = begin[from] + length[from]; p < end; ++p) {
            const uint32_t c = rows.index[p];
            if (!touched[c]) touched[c] = 1, list.push_back(c);
            acc[c] += w * rows.value[p];
          }
        };
        add(t, 1.0);
        for (uint32_t k = step.offsets[r]; k < step.offsets[r + 1]; ++k) add(step.sources[k], step.weights[k]);
        std::sort(list.begin(), list.end());
        begin[t] = rows.index.size(), length[t] = 0;
        for (uint32_t c : list) {
          if (acc[c] != 0.0) rows.index.push_back(c), rows.value.push_back(acc[c]), ++length[t];
          acc[c] = 0.0, touched[c] = 0;
        }
        list.clear();
      }
    }
    size_t live = 0;
    for (uint32_t v = 0; v < h.vertexCount[l]; ++v) live += length[v];
    compactIndex.clear(), compactValue.clear();
    compactIndex.reserve(live), compactValue.reserve(live);
    for (uint32_t v = 0; v < h.vertexCount[l]; ++v) {
      const uint64_t b = begin[v];
      begin[v] = compactIndex.size();
      compactIndex.insert(compactIndex.end(), rows.index.begin() + b, rows.index.begin() + b + length[v]);
      compactValue.insert(compactValue.end(), rows.value.begin() + b, rows.value.begin() + b + length[v]);
    }
    std::swap(rows.index, compactIndex), std::swap(rows.value, compactValue);
  }
  // After the last compaction (or none) the rows lie in vertex order.
  rows.offset.resize(n + 1);
  for (size_t v = 0; v < n; ++v) rows.offset[v] = begin[v];
  rows.offset[n] = rows.index.size();
  return rows;
}

namespace {

// The level-e face holding each fine triangle. Each vertex's place in the level-e mesh first, in
// hierarchy order (a vertex's ends come before it): at a cage vertex, on a level-e edge or inside a
// level-e face; a vertex born at the midpoint of its ends lies inside the face of an end that lies
// inside one, else on the edge or inside the face the cage vertices of its ends' places span. A
// triangle lies in the face of a vertex inside one, else in the face of its vertices' cage vertices.
// Also each region's fine vertices, ascending, in [vertexStart[r], vertexStart[r + 1]) of
// `vertices`: a vertex inside a level-e face is that face's, one on a level-e edge the faces' on
// both sides, a cage vertex the faces' around it (the vertices of the region's triangles), bucketed
// in one pass over the vertices in order (no gathering and sorting per region).
struct RegionsOfTriangles {
  std::vector<uint32_t> region, vertexStart, vertices;
};
RegionsOfTriangles regionOfTriangles(const Hierarchy& h, int level) {
  const auto& coarse = h.faces[level];
  VertexCorners corners(coarse.data(), coarse.size() / 3, h.vertexCount[level]);
  const auto faceOf = [&](uint32_t a, uint32_t b, uint32_t c) {
    for (uint32_t k = corners.begin(a); k < corners.end(a); ++k)
      if ((corners.next[k] == b && corners.prev[k] == c) || (corners.next[k] == c && corners.prev[k] == b)) return corners.face[k];
    return kNone;
  };
  // Place: a cage vertex (a, kNone), a level-e edge (a < b) or a level-e face (kNone, face).
  struct Place { uint32_t a, b; };
  const size_t n = h.fineVertexCount();
  const uint32_t cage = h.vertexCount[level];
  std::vector<Place> place(n);
  for (uint32_t v = 0; v < cage; ++v) place[v] = {v, kNone};
  // The face of the cage vertices of some places (kNone when they span no face or more than one).
  const auto spanned = [&](const Place* places, int count) {
    uint32_t u[6];
    int m = 0;
    for (int i = 0; i < count; ++i)
      for (uint32_t x : {places[i].a, places[i].b})
        if (x != kNone && std::find(u, u + m, x) == u + m) u[m++] = x;
    return m == 3 ? faceOf(u[0], u[1], u[2]) : kNone;
  };
  for (size_t v = cage; v < n; ++v) {
    const Place ends[2] = {place[h.ends[2 * v]], place[h.ends[2 * v + 1]]};
    const bool inside0 = ends[0].a == kNone, inside1 = ends[1].a == kNone;
    if (inside0 || inside1) {
      if (inside0 && inside1 && ends[0].b != ends[1].b)
        throw Error("vertex " + std::to_string(v) + " has its ends inside two level-" + std::to_string(level) + " faces");
      place[v] = inside0 ? ends[0] : ends[1];
      continue;
    }
    uint32_t u[4];
    int m = 0;
    for (const Place& e : ends)
      for (uint32_t x : {e.a, e.b})
        if (x != kNone && std::find(u, u + m, x) == u + m) u[m++] = x;
    if (m == 2) {
      place[v] = {std::min(u[0], u[1]), std::max(u[0], u[1])};
    } else {
      const uint32_t face = spanned(ends, 2);
      if (face == kNone) throw Error("vertex " + std::to_string(v) + " lies in no level-" + std::to_string(level) + " face");
      place[v] = {kNone, face};
    }
  }
  const auto& fine = h.fineFaces();
  std::vector<uint32_t> region(fine.size() / 3);
  for (size_t t = 0; t < region.size(); ++t) {
    const Place p[3] = {place[fine[3 * t]], place[fine[3 * t + 1]], place[fine[3 * t + 2]]};
    uint32_t face = kNone;
    bool twoFaces = false;
    for (const Place& x : p)
      if (x.a == kNone) twoFaces = twoFaces || (face != kNone && face != x.b), face = x.b;
    if (face == kNone) face = spanned(p, 3);
    if (face == kNone || twoFaces)
      throw Error("fine triangle " + std::to_string(t) + " lies in no level-" + std::to_string(level) + " face");
    region[t] = face;
  }
  const size_t regions = coarse.size() / 3;
  const auto forRegionsOf = [&](uint32_t v, auto&& f) {
    const Place& p = place[v];
    if (p.a == kNone) return f(p.b);
    if (p.b == kNone) {
      for (uint32_t k = corners.begin(p.a); k < corners.end(p.a); ++k) f(corners.face[k]);
      return;
    }
    for (const uint32_t k : {corners.cornerTo(p.a, p.b), corners.cornerTo(p.b, p.a)})
      if (k != kNone) f(corners.face[k]);
  };
  RegionsOfTriangles out;
  out.vertexStart.assign(regions + 1, 0);
  for (uint32_t v = 0; v < n; ++v) forRegionsOf(v, [&](uint32_t r) { ++out.vertexStart[r + 1]; });
  for (size_t r = 0; r < regions; ++r) out.vertexStart[r + 1] += out.vertexStart[r];
  out.vertices.resize(out.vertexStart[regions]);
  std::vector<uint32_t> fill(out.vertexStart.begin(), out.vertexStart.end() - 1);
  for (uint32_t v = 0; v < n; ++v) forRegionsOf(v, [&](uint32_t r) { out.vertices[fill[r]++] = v; });
  out.region = std::move(region);
  return out;
}

// Index of the pair (i, j), i < j, among the pairs of [0, S) in lexicographic order.
inline size_t pairIndex(size_t i, size_t j, size_t S) { return i * (2 * S - i - 1) / 2 + (j - i - 1); }

// A term's key after its first cage vertex ((j, k) or j), and where its slot goes.
struct Keyed {
  uint64_t key, position;
};

// Sorts [begin, end) by key; each distinct key gets a slot from newSlot(key) (in ascending order),
// written to slot[position] for each of its copies.
template <class NewSlot>
void uniqueKeys(Keyed* begin, Keyed* end, NewSlot&& newSlot, uint32_t* slot) {
  std::sort(begin, end, [](const Keyed& x, const Keyed& y) { return x.key < y.key; });
  uint32_t current = 0;
  for (Keyed* p = begin; p < end; ++p) {
    if (p == begin || p->key != p[-1].key) current = newSlot(p->key);
    slot[p->position] = current;
  }
}

}  // namespace

namespace {

int checkedLevel(const Hierarchy& h, int level) {
  if (level < 0 || level > h.levels)
    throw Error("level " + std::to_string(level) + " is out of range: this mesh has levels 0.." + std::to_string(h.levels));
  return level;
}

// The fine triangles with weight 1/6 by level-e face, each carried by its corner with x - y = 0
// mod 3 in the face's lattice coordinates (x, y >= 0, x + y <= side: corners at (0, 0), (side, 0),
// (0, side), a vertex born later at the midpoint of its ends): every fine triangle has one.
RegionForm triangleRegions(const Hierarchy& h, int level) {
  checkedLevel(h, level);
  RegionsOfTriangles regionsOf = regionOfTriangles(h, level);
  const std::vector<uint32_t>& regionOf = regionsOf.region;
  const auto& faces = h.fineFaces();
  const size_t regions = h.faces[level].size() / 3;
  std::vector<uint32_t> triangleStart(regions + 1, 0), triangles(regionOf.size());
  for (uint32_t r : regionOf) ++triangleStart[r + 1];
  std::partial_sum(triangleStart.begin(), triangleStart.end(), triangleStart.begin());
  {
    std::vector<uint32_t> fill(triangleStart.begin(), triangleStart.end() - 1);
    for (size_t t = 0; t < regionOf.size(); ++t) triangles[fill[regionOf[t]]++] = uint32_t(t);
  }
  const uint32_t cageSize = h.vertexCount[level];
  const int64_t side = int64_t(1) << (h.levels - level);  // lattice steps along a level-e edge
  RegionForm out;
  out.regionCount = regions;
  out.form.corners.resize(faces.size());
  out.form.weights.assign(regionOf.size(), 1.0 / 6.0);
  out.region.resize(regionOf.size());
  uint32_t* cornerOut = out.form.corners.data();
  uint32_t* regionOut = out.region.data();
  std::vector<uint32_t> localOf(h.fineVertexCount(), kNone);
  std::vector<int64_t> coordX, coordY;
  std::vector<uint8_t> carries;  // per region vertex: x - y = 0 mod 3
  for (size_t r = 0; r < regions; ++r) {
    // Its fine vertices, ascending: by depth, so that the ends of a vertex come before it.
    const uint32_t* vertices = regionsOf.vertices.data() + regionsOf.vertexStart[r];
    const uint32_t count = regionsOf.vertexStart[r + 1] - regionsOf.vertexStart[r];
    for (uint32_t i = 0; i < count; ++i) localOf[vertices[i]] = i;
    coordX.assign(count, 0), coordY.assign(count, 0);
    const uint32_t* corner = &h.faces[level][3 * r];
    for (uint32_t i = 0; i < count; ++i) {
      const uint32_t v = vertices[i];
      if (v < cageSize) {
        const int k = v == corner[0] ? 0 : v == corner[1] ? 1 : v == corner[2] ? 2 : -1;
        if (k < 0) throw Error("cage vertex " + std::to_string(v) + " lies inside level-" + std::to_string(level) + " face " + std::to_string(r));
        coordX[i] = k == 1 ? side : 0, coordY[i] = k == 2 ? side : 0;
      } else {
        const uint32_t a = localOf[h.ends[2 * size_t(v)]], b = localOf[h.ends[2 * size_t(v) + 1]];
        if (a == kNone || b == kNone || a >= i || b >= i)
          throw Error("vertex " + std::to_string(v) + " has an end outside level-" + std::to_string(level) + " face " + std::to_string(r));
        coordX[i] = (coordX[a] + coordX[b]) / 2, coordY[i] = (coordY[a] + coordY[b]) / 2;
      }
    }
    carries.resize(count);
    for (uint32_t i = 0; i < count; ++i) carries[i] = ((coordX[i] - coordY[i]) % 3 + 3) % 3 == 0;
    for (uint32_t p = triangleStart[r]; p < triangleStart[r + 1]; ++p) {
      const uint32_t* t = &faces[3 * size_t(triangles[p])];
      int k = 0;
      while (k < 3 && !carries[localOf[t[k]]]) ++k;
      if (k == 3) throw Error("fine triangle " + std::to_string(triangles[p]) + " is not a lattice triangle of its level-" + std::to_string(level) + " face");
      cornerOut[0] = t[k], cornerOut[1] = t[(k + 1) % 3], cornerOut[2] = t[(k + 2) % 3];
      cornerOut += 3;
      *regionOut++ = uint32_t(r);
    }
    for (uint32_t i = 0; i < count; ++i) localOf[vertices[i]] = kNone;
  }
  out.vertexStart = std::move(regionsOf.vertexStart);
  out.vertices = std::move(regionsOf.vertices);
  return out;
}

}  // namespace

CagePolynomialBuilder::CagePolynomialBuilder(const WaveletTransform& transform, int level, uint64_t maxTerms, CageBasis* basisOut)
    : CagePolynomialBuilder(transform, level, triangleRegions(transform.hierarchy(), level), maxTerms, basisOut) {}

CagePolynomialBuilder::CagePolynomialBuilder(const WaveletTransform& transform, int level, const RegionForm& regionForm,
                                             uint64_t maxTerms, CageBasis* basisOut)
    : transform_(&transform), level_(level) {
  const Hierarchy& h = transform.hierarchy();
  checkedLevel(h, level);
  cageSize_ = h.vertexCount[level];
  const size_t n = h.fineVertexCount();
  const FineForm& form = regionForm.form;
  if (form.corners.size() != 3 * form.size() || regionForm.region.size() != form.size())
    throw Error("the volume form needs 3 corners and a region per term");
  for (uint32_t v : form.corners)
    if (v >= n) throw Error("the volume form names vertex " + std::to_string(v) + " of a mesh of " + std::to_string(n));
  CageBasis basis = cageBasis(transform, level);
  basisEntries_ = basis.index.size();

  // Terms by region (counting sort).
  const size_t regions = regionForm.regionCount;
  std::vector<uint32_t> termStart(regions + 1, 0), terms(form.size());
  for (uint32_t r : regionForm.region) {
    if (r >= regions) throw Error("the volume form names region " + std::to_string(r) + " of " + std::to_string(regions));
    ++termStart[r + 1];
  }
  std::partial_sum(termStart.begin(), termStart.end(), termStart.begin());
  {
    std::vector<uint32_t> fill(termStart.begin(), termStart.end() - 1);
    for (size_t t = 0; t < form.size(); ++t) terms[fill[regionForm.region[t]]++] = uint32_t(t);
  }

  std::vector<uint32_t> localOf(n, kNone), slotOf(cageSize_, kNone);
  struct Carried { uint32_t a, b, c; double w; };
  std::vector<Carried> carried, sortedCarried;
  std::vector<uint32_t> runCount;
  regionCage_.assign(1, 0), regionVertex_.assign(1, 0), regionWeight_.assign(1, 0), regionRun_.assign(1, 0);
  regionTriple_.assign(1, 0), regionPair_.assign(1, 0);
  runStart_.assign(1, 0);
  triangleB_.reserve(form.size()), triangleC_.reserve(form.size()), triangleWeight_.reserve(form.size());
  regionCage_.reserve(regions + 1), regionVertex_.reserve(regions + 1), regionWeight_.reserve(regions + 1);
  regionRun_.reserve(regions + 1), regionTriple_.reserve(regions + 1), regionPair_.reserve(regions + 1);
  const bool vertexListsGiven = regionForm.vertexStart.size() == regions + 1;
  if (vertexListsGiven) vertex_.reserve(regionForm.vertices.size());
  uint64_t weightEnd = 0;
  for (size_t r = 0; r < regions; ++r) {
    // Its fine vertices, ascending.
    const size_t vertexBegin = vertex_.size();
    if (vertexListsGiven) {
      vertex_.insert(vertex_.end(), regionForm.vertices.begin() + regionForm.vertexStart[r],
                     regionForm.vertices.begin() + regionForm.vertexStart[r + 1]);
    } else {
      for (uint32_t p = termStart[r]; p < termStart[r + 1]; ++p)
        for (int k = 0; k < 3; ++k) {
          const uint32_t v = form.corners[3 * size_t(terms[p]) + k];
          if (localOf[v] == kNone) localOf[v] = 0, vertex_.push_back(v);
        }
      std::sort(vertex_.begin() + vertexBegin, vertex_.end());
    }
    const uint32_t count = uint32_t(vertex_.size() - vertexBegin);
    for (uint32_t i = 0; i < count; ++i) localOf[vertex_[vertexBegin + i]] = i;

    // Its influencing cage vertices, ascending (local order = cage order), and the dense weights.
    const size_t cageBegin = cage_.size();
    for (uint32_t i = 0; i < count; ++i) {
      const uint32_t v = vertex_[vertexBegin + i];
      for (uint64_t p = basis.offset[v]; p < basis.offset[v + 1]; ++p)
        if (slotOf[basis.index[p]] == kNone) slotOf[basis.index[p]] = 0, cage_.push_back(basis.index[p]);
    }
    std::sort(cage_.begin() + cageBegin, cage_.end());
    const size_t s = cage_.size() - cageBegin;
    maxCage_ = std::max(maxCage_, s);
    weightEnd += uint64_t(count) * s;  // its dense weights: filled below, once all sizes are known

    // The terms in runs of one carrying vertex (their first corner).
    carried.clear();
    carried.reserve(termStart[r + 1] - termStart[r]);
    for (uint32_t p = termStart[r]; p < termStart[r + 1]; ++p) {
      const uint32_t* t = &form.corners[3 * size_t(terms[p])];
      carried.push_back({localOf[t[0]], localOf[t[1]], localOf[t[2]], form.weights[terms[p]]});
    }
    {  // stably by carrying vertex: a counting sort (local indices < count)
      runCount.assign(size_t(count) + 1, 0);
      for (const Carried& t : carried) ++runCount[t.a + 1];
      std::partial_sum(runCount.begin(), runCount.end(), runCount.begin());
      sortedCarried.resize(carried.size());
      for (const Carried& t : carried) sortedCarried[runCount[t.a]++] = t;
      std::swap(carried, sortedCarried);
    }
    for (size_t p = 0; p < carried.size(); ++p) {
      if (p == 0 || carried[p].a != carried[p - 1].a) {
        if (p > 0) runStart_.push_back(uint32_t(triangleB_.size()));
        runVertex_.push_back(carried[p].a);
      }
      triangleB_.push_back(carried[p].b), triangleC_.push_back(carried[p].c), triangleWeight_.push_back(carried[p].w);
    }
    if (!carried.empty()) runStart_.push_back(uint32_t(triangleB_.size()));

    // The terms it touches: every triple and pair of its cage vertices (slots made below).
    const uint64_t triples = uint64_t(s) * (s - 1) * (s - 2) / 6;
    if (regionTriple_.back() + triples > maxTerms)
      throw Error("the level-" + std::to_string(level) + " cage polynomial would touch more than " + std::to_string(maxTerms) +
                  " cage triples (" + std::to_string(cageSize_) + " cage vertices): use the matrix-free path at this level");
    regionTriple_.push_back(regionTriple_.back() + triples);
    regionPair_.push_back(regionPair_.back() + uint64_t(s) * (s - 1) / 2);

    for (uint32_t i = 0; i < count; ++i) localOf[vertex_[vertexBegin + i]] = kNone;
    for (size_t i = 0; i < s; ++i) slotOf[cage_[cageBegin + i]] = kNone;
    regionCage_.push_back(uint32_t(cage_.size()));
    regionVertex_.push_back(uint32_t(vertex_.size()));
    regionWeight_.push_back(weightEnd);
    regionRun_.push_back(uint32_t(runVertex_.size()));
  }

  // The dense weights, one row of s per region vertex: allocated once, the regions on the pool's
  // threads (each writes its own rows).
  localOf = {}, slotOf = {};
  weight_.assign(weightEnd, 0.0);
  parallelFor(0, regions, 1, [&](size_t first, size_t end) {
    std::vector<uint32_t> slot(cageSize_, kNone);
    for (size_t r = first; r < end; ++r) {
      const uint32_t* g = &cage_[regionCage_[r]];
      const size_t s = regionCage_[r + 1] - regionCage_[r];
      for (size_t i = 0; i < s; ++i) slot[g[i]] = uint32_t(i);
      double* w = &weight_[regionWeight_[r]];
      for (uint32_t i = regionVertex_[r]; i < regionVertex_[r + 1]; ++i, w += s) {
        const uint32_t v = vertex_[i];
        for (uint64_t p = basis.offset[v]; p < basis.offset[v + 1]; ++p) w[slot[basis.index[p]]] = basis.value[p];
      }
      for (size_t i = 0; i < s; ++i) slot[g[i]] = kNone;
    }
  });

  // The polynomial's terms: the union over the regions, ascending; each region's slots into it.
  // Keys bucketed by their first cage vertex (a counting sort), each bucket sorted by the rest.
  std::vector<uint64_t> tripleStart(size_t(cageSize_) + 1, 0), pairStart(size_t(cageSize_) + 1, 0);
  for (size_t r = 0; r < regions; ++r) {
    const uint32_t* g = &cage_[regionCage_[r]];
    const size_t s = regionCage_[r + 1] - regionCage_[r];
    for (size_t i = 0; i < s; ++i) {
      const uint64_t rest = s - 1 - i;
      tripleStart[g[i] + 1] += rest * (rest - (rest > 0)) / 2, pairStart[g[i] + 1] += rest;
    }
  }
  std::partial_sum(tripleStart.begin(), tripleStart.end(), tripleStart.begin());
  std::partial_sum(pairStart.begin(), pairStart.end(), pairStart.begin());
  std::vector<Keyed> keys(tripleStart.back());
  {
    std::vector<uint64_t> fill(tripleStart.begin(), tripleStart.end() - 1);
    for (size_t r = 0; r < regions; ++r) {
      const uint32_t* g = &cage_[regionCage_[r]];
      const size_t s = regionCage_[r + 1] - regionCage_[r];
      uint64_t position = regionTriple_[r];
      for (size_t i = 0; i < s; ++i)
        for (size_t j = i + 1; j < s; ++j)
          for (size_t k = j + 1; k < s; ++k) keys[fill[g[i]]++] = {uint64_t(g[j]) << 32 | g[k], position++};
    }
  }
  tripleSlot_.resize(keys.size());
  for (uint32_t c = 0; c < cageSize_; ++c)
    uniqueKeys(keys.data() + tripleStart[c], keys.data() + tripleStart[c + 1], [&](uint64_t key) {
      tripleI_.push_back(c), tripleJ_.push_back(uint32_t(key >> 32)), tripleK_.push_back(uint32_t(key));
      return uint32_t(tripleI_.size() - 1);
    }, tripleSlot_.data());
  keys.assign(pairStart.back(), Keyed{});
  {
    std::vector<uint64_t> fill(pairStart.begin(), pairStart.end() - 1);
    for (size_t r = 0; r < regions; ++r) {
      const uint32_t* g = &cage_[regionCage_[r]];
      const size_t s = regionCage_[r + 1] - regionCage_[r];
      uint64_t position = regionPair_[r];
      for (size_t i = 0; i < s; ++i)
        for (size_t j = i + 1; j < s; ++j) keys[fill[g[i]]++] = {g[j], position++};
    }
  }
  pairSlot_.resize(keys.size());
  for (uint32_t c = 0; c < cageSize_; ++c)
    uniqueKeys(keys.data() + pairStart[c], keys.data() + pairStart[c + 1], [&](uint64_t key) {
      pairI_.push_back(c), pairJ_.push_back(uint32_t(key));
      return uint32_t(pairI_.size() - 1);
    }, pairSlot_.data());
  if (basisOut) *basisOut = std::move(basis);
}

size_t CagePolynomialBuilder::bytes() const {
  auto b = [](const auto& v) { return v.size() * sizeof(v[0]); };
  return b(regionCage_) + b(regionVertex_) + b(regionWeight_) + b(regionRun_) + b(regionTriple_) + b(regionPair_) +
         b(cage_) + b(vertex_) + b(weight_) + b(runVertex_) + b(runStart_) + b(triangleB_) + b(triangleC_) + b(triangleWeight_) +
         b(tripleSlot_) + b(pairSlot_) + b(tripleI_) + b(tripleJ_) + b(tripleK_) + b(pairI_) + b(pairJ_);
}

void CagePolynomialBuilder::regionMinors(size_t r, const double* detail, std::vector<double>& w, std::vector<double>& wedges,
                                         std::vector<double>& outer, double* out) const {
  const size_t s = regionCage_[r + 1] - regionCage_[r], S = s + 3, P = S * (S - 1) / 2;
  const uint32_t vertexBegin = regionVertex_[r], count = regionVertex_[r + 1] - vertexBegin;
  // Rows w_v = (cage weights, D_v) of the region's vertices.
  w.resize(size_t(count) * S);
  const double* weights = &weight_[regionWeight_[r]];
  for (uint32_t i = 0; i < count; ++i) {
    std::copy(weights + size_t(i) * s, weights + size_t(i + 1) * s, &w[size_t(i) * S]);
    std::copy(&detail[3 * size_t(vertex_[vertexBegin + i])], &detail[3 * size_t(vertex_[vertexBegin + i]) + 3], &w[size_t(i) * S + s]);
  }
  // outer = sum over the carrying vertices a of w_a (x) G_a, G_a = sum of w_t w_b ^ w_c (packed i < j).
  outer.assign(S * P, 0.0);
  // The runs four at a time: their G side by side, then each entry of outer takes the four updates
  // in run order in one pass (the same additions in the same order as run by run, a quarter of the
  // loads and stores of outer). A zero weight's update adds a zero, which leaves any entry as it is
  // (outer starts at +0 and a sum of nonzeros never rounds to -0), so skipping it is only for speed.
  constexpr size_t kRuns = 4;
  wedges.resize(kRuns * P);
  // A run's G four triangles at a time: each entry takes their four updates in registers, in run
  // order (the same additions in the same order as triangle by triangle, a quarter of the loads and
  // stores of G). A row whose four (b_i, c_i) are all zero is skipped; within a group a zero pair
  // adds a zero, which leaves any entry as it is (G starts at +0 and never becomes -0).
  const auto runWedges = [&](uint32_t run, double* wedge) {
    std::fill(wedge, wedge + P, 0.0);
    uint32_t t = runStart_[run];
    const uint32_t end = runStart_[run + 1];
    for (; t + 4 <= end; t += 4) {
      const double *b0 = &w[size_t(triangleB_[t]) * S], *c0 = &w[size_t(triangleC_[t]) * S];
      const double *b1 = &w[size_t(triangleB_[t + 1]) * S], *c1 = &w[size_t(triangleC_[t + 1]) * S];
      const double *b2 = &w[size_t(triangleB_[t + 2]) * S], *c2 = &w[size_t(triangleC_[t + 2]) * S];
      const double *b3 = &w[size_t(triangleB_[t + 3]) * S], *c3 = &w[size_t(triangleC_[t + 3]) * S];
      const double w0 = triangleWeight_[t], w1 = triangleWeight_[t + 1], w2 = triangleWeight_[t + 2], w3 = triangleWeight_[t + 3];
      double* g = wedge;
      for (size_t i = 0; i + 1 < S; ++i) {
        const size_t len = S - i - 1;
        const double bi0 = w0 * b0[i], ci0 = w0 * c0[i], bi1 = w1 * b1[i], ci1 = w1 * c1[i];
        const double bi2 = w2 * b2[i], ci2 = w2 * c2[i], bi3 = w3 * b3[i], ci3 = w3 * c3[i];
        if (bi0 != 0.0 || ci0 != 0.0 || bi1 != 0.0 || ci1 != 0.0 || bi2 != 0.0 || ci2 != 0.0 || bi3 != 0.0 || ci3 != 0.0)
          for (size_t j = 0, k = i + 1; j < len; ++j, ++k) {
            double x = g[j];
            x += bi0 * c0[k] - ci0 * b0[k];
            x += bi1 * c1[k] - ci1 * b1[k];
            x += bi2 * c2[k] - ci2 * b2[k];
            x += bi3 * c3[k] - ci3 * b3[k];
            g[j] = x;
          }
        g += len;
      }
    }
    for (; t < end; ++t) {
      const double *wb = &w[size_t(triangleB_[t]) * S], *wc = &w[size_t(triangleC_[t]) * S];
      const double weight = triangleWeight_[t];
      double* g = wedge;
      for (size_t i = 0; i + 1 < S; ++i) {
        const double bi = weight * wb[i], ci = weight * wc[i];
        const size_t len = S - i - 1;
        if (bi != 0.0 || ci != 0.0)
          for (size_t j = 0; j < len; ++j) g[j] += bi * wc[i + 1 + j] - ci * wb[i + 1 + j];
        g += len;
      }
    }
  };
  uint32_t run = regionRun_[r];
  for (; run + kRuns <= regionRun_[r + 1]; run += kRuns) {
    for (size_t q = 0; q < kRuns; ++q) runWedges(run + uint32_t(q), &wedges[q * P]);
    const double *g0 = &wedges[0], *g1 = &wedges[P], *g2 = &wedges[2 * P], *g3 = &wedges[3 * P];
    const double *wa0 = &w[size_t(runVertex_[run]) * S], *wa1 = &w[size_t(runVertex_[run + 1]) * S],
                 *wa2 = &w[size_t(runVertex_[run + 2]) * S], *wa3 = &w[size_t(runVertex_[run + 3]) * S];
    for (size_t i = 0; i < S; ++i) {
      const double a0 = wa0[i], a1 = wa1[i], a2 = wa2[i], a3 = wa3[i];
      if (a0 == 0.0 && a1 == 0.0 && a2 == 0.0 && a3 == 0.0) continue;
      double* o = &outer[i * P];
      for (size_t p = 0; p < P; ++p) o[p] = o[p] + a0 * g0[p] + a1 * g1[p] + a2 * g2[p] + a3 * g3[p];
    }
  }
  for (; run < regionRun_[r + 1]; ++run) {
    runWedges(run, wedges.data());
    const double* wa = &w[size_t(runVertex_[run]) * S];
    for (size_t i = 0; i < S; ++i) {
      const double a = wa[i];
      if (a == 0.0) continue;
      double* o = &outer[i * P];
      for (size_t p = 0; p < P; ++p) o[p] += a * wedges[p];
    }
  }
  // The 3 x 3 minors, alternated out of outer, in the order build() adds them to the terms:
  // (i, j, k) all cage: a triple; (i, j, D_d): q_ij[d]; (i, D_d1, D_d2): a_i through
  // det(x_i, e_d1, e_d2); (D, D, D): the constant.
  auto minor = [&](size_t i, size_t j, size_t k) {
    return outer[i * P + pairIndex(j, k, S)] - outer[j * P + pairIndex(i, k, S)] + outer[k * P + pairIndex(i, j, S)];
  };
  for (size_t i = 0; i < s; ++i) {
    for (size_t j = i + 1; j < s; ++j) {
      for (size_t k = j + 1; k < s; ++k) *out++ = minor(i, j, k);
      for (int d = 0; d < 3; ++d) *out++ = minor(i, j, s + d);
    }
    *out++ = minor(i, s + 1, s + 2), *out++ = minor(i, s, s + 2), *out++ = minor(i, s, s + 1);
  }
  *out = minor(s, s + 1, s + 2);
}

CagePolynomial CagePolynomialBuilder::build(const double* coefficients) const {
  const Hierarchy& h = transform_->hierarchy();
  const size_t n3 = 3 * h.fineVertexCount(), cage3 = 3 * size_t(cageSize_);
  // D: the details synthesized with a zero cage (the cage coefficients are not read).
  std::vector<double> detail(coefficients, coefficients + n3);
  std::fill(detail.begin(), detail.begin() + cage3, 0.0);
  transform_->synthesize(detail.data(), level_);

  std::vector<double> triple(tripleI_.size(), 0.0), pair(3 * pairI_.size(), 0.0), linear(cage3, 0.0);
  double constant = 0;
  // Each region's minors (its C(s, 3) triples, 3 C(s, 2) pair entries, 3 s linear entries and a
  // constant) are formed on the pool's threads, a chunk of regions at a time, then added to the
  // terms in region order: the same sums in the same order at any thread count.
  const size_t regions = regionCage_.size() - 1;
  const auto regionSize = [&](size_t r) { return size_t(regionCage_[r + 1] - regionCage_[r]); };
  const auto minorCount = [&](size_t r) {
    const size_t s = regionSize(r);
    return size_t(regionTriple_[r + 1] - regionTriple_[r]) + 3 * size_t(regionPair_[r + 1] - regionPair_[r]) + 3 * s + 1;
  };
  std::vector<size_t> minorStart;
  std::vector<double> minors;
  for (size_t chunk = 0; chunk < regions; chunk += kRegionsPerChunk) {
    const size_t chunkEnd = std::min(regions, chunk + kRegionsPerChunk);
    minorStart.assign(1, 0);
    for (size_t r = chunk; r < chunkEnd; ++r) minorStart.push_back(minorStart.back() + minorCount(r));
    minors.resize(minorStart.back());
    parallelFor(chunk, chunkEnd, 1, [&](size_t first, size_t end) {
      std::vector<double> w, wedges, outer;
      for (size_t r = first; r < end; ++r) regionMinors(r, detail.data(), w, wedges, outer, &minors[minorStart[r - chunk]]);
    });
    for (size_t r = chunk; r < chunkEnd; ++r) {
      const size_t s = regionSize(r);
      const uint32_t* g = &cage_[regionCage_[r]];
      const uint32_t* tripleSlot = &tripleSlot_[regionTriple_[r]];
      const uint32_t* pairSlot = &pairSlot_[regionPair_[r]];
      const double* m = &minors[minorStart[r - chunk]];
      size_t t = 0, p = 0;
      for (size_t i = 0; i < s; ++i) {
        for (size_t j = i + 1; j < s; ++j) {
          for (size_t k = j + 1; k < s; ++k) triple[tripleSlot[t++]] += *m++;
          double* q = &pair[3 * size_t(pairSlot[p++])];
          for (int d = 0; d < 3; ++d) q[d] += *m++;
        }
        double* a = &linear[3 * size_t(g[i])];
        a[0] += m[0], a[1] -= m[1], a[2] += m[2];
        m += 3;
      }
      constant += *m;
    }
  }

  CagePolynomial poly;
  poly.cageSize = cageSize_;
  poly.constant = constant;
  poly.linear = std::move(linear);
  // Terms whose coefficient is exactly zero (supports that never meet on a triangle) are dropped.
  for (size_t p = 0; p < pairI_.size(); ++p)
    if (pair[3 * p] != 0.0 || pair[3 * p + 1] != 0.0 || pair[3 * p + 2] != 0.0) {
      poly.pairI.push_back(pairI_[p]), poly.pairJ.push_back(pairJ_[p]);
      poly.pairQ.insert(poly.pairQ.end(), &pair[3 * p], &pair[3 * p] + 3);
    }
  for (size_t p = 0; p < tripleI_.size(); ++p)
    if (triple[p] != 0.0) {
      poly.tripleI.push_back(tripleI_[p]), poly.tripleJ.push_back(tripleJ_[p]), poly.tripleK.push_back(tripleK_[p]);
      poly.tripleT.push_back(triple[p]);
    }
  return poly;
}

}  // namespace mrvol
