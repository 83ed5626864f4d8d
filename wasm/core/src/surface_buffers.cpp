#include "mrvol/surface_buffers.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "mrvol/thread_pool.h"
#include "mrvol/volume_editor.h"

#ifdef __wasm_simd128__
#include <wasm_simd128.h>
#endif

namespace mrvol {

SurfaceBuffers::SurfaceBuffers(const Hierarchy& hierarchy)
    : hierarchy_(&hierarchy), vertexCount_(hierarchy.fineVertexCount()) {
  callerIsHierarchyOrder_ = true;
  for (size_t h = 0; h < vertexCount_ && callerIsHierarchyOrder_; ++h) callerIsHierarchyOrder_ = hierarchy.inputIndex[h] == h;
  // One float more than 3 N: a vector store per vertex runs over by one.
  positions_.assign(3 * vertexCount_ + 1, 0.0f);
  normals_.assign(3 * vertexCount_ + 1, 0.0f);
  mark_.assign(vertexCount_, 0);
}

void SurfaceBuffers::merge(FinePositions::Changes& into, const FinePositions::Changes& changes) {
  if (into.whole) return;
  if (changes.whole) {
    into = FinePositions::Changes{};
    return;
  }
  into.vertices.insert(into.vertices.end(), changes.vertices.begin(), changes.vertices.end());
}

void SurfaceBuffers::update(const VolumeEditor& editor, bool withNormals) {
  if (ringStart_.empty()) buildRing();
  if (!tableTried_) {
    tableTried_ = true;
    if (editor.cageSize() <= CageBasisTable::kMaxCage) {
      // Rows in the buffers' own (local) order.
      std::vector<uint32_t> rowOf(vertexCount_);
      for (size_t h = 0; h < vertexCount_; ++h) rowOf[h] = slot_[hierarchy_->inputIndex[h]];
      const std::unique_ptr<CageBasis> basis = editor.takeCageBasis();  // the polynomial builder's, if any
      table_ = basis ? std::make_unique<CageBasisTable>(*basis, editor.cageSize(), rowOf.data())
                     : std::make_unique<CageBasisTable>(editor.transform(), editor.level(), rowOf.data());
      if (table_->empty()) table_.reset();
    }
  }
  if (!table_) {
    const double* fine = editor.finePositions().data();
    FinePositions::Changes changes;
    editor.takeFinePositionChanges(changes);
    update(fine, editor.referencePoint(), editor.finePositionsVersion(), changes, withNormals);
    return;
  }
  const uint32_t cageSize = editor.cageSize();
  const size_t cage3 = 3 * size_t(cageSize);
  const double* cage = editor.coefficientData();
  const Vec3 o = editor.referencePoint();
  const float origin[3] = {float(o.x), float(o.y), float(o.z)};
  if (!haveBase_ || baseDetails_ != editor.detailsVersion()) {
    // A base from a synthesis (the first time, and after the details moved).
    const double* fine = editor.finePositions().data();
    FinePositions::Changes changes;
    editor.takeFinePositionChanges(changes);
    pendingPositions_ = FinePositions::Changes{};
    writePositions(fine, o);
    writeRelative(fine);
    base_ = relative_;
    baseCage_.assign(cage, cage + cage3);
    delta_.assign(4 * size_t(cageSize), 0.0f);
    baseDetails_ = editor.detailsVersion();
    haveBase_ = true;
  } else {
    moved_.clear();
    size_t rows = 0;
    for (uint32_t c = 0; c < cageSize; ++c) {
      const double* x = cage + 3 * size_t(c);
      const double* was = writtenCage_.data() + 3 * size_t(c);
      if (x[0] == was[0] && x[1] == was[1] && x[2] == was[2]) continue;
      moved_.push_back(c);
      for (int k = 0; k < 3; ++k) delta_[4 * size_t(c) + k] = float(x[k] - baseCage_[3 * size_t(c) + k]);
      rows += size_t(table_->columnEnd(c) - table_->columnBegin(c));
    }
    if (moved_.empty()) {
      if (withNormals) writeTableNormals();
      return;
    }
    if (rows <= vertexCount_ / 8) {
      // A few cage vertices moved: only the rows of their columns.
      if (++markRound_ == 0) std::fill(mark_.begin(), mark_.end(), 0), markRound_ = 1;
      rows_.clear();
      for (uint32_t c : moved_)
        for (const uint32_t* v = table_->columnBegin(c); v != table_->columnEnd(c); ++v)
          if (mark_[*v] != markRound_) mark_[*v] = markRound_, rows_.push_back(*v);
      table_->applyRows(rows_.data(), rows_.size(), base_.data(), delta_.data(), origin, relative_.data(), positions_.data(),
                        order_.data());
      uint32_t first = UINT32_MAX, end = 0;
      for (uint32_t i : rows_) first = std::min(first, order_[i]), end = std::max(end, order_[i] + 1);
      positionsRange_[0] = first == UINT32_MAX ? 0 : first, positionsRange_[1] = end;
      for (uint32_t c : moved_) std::copy(cage + 3 * size_t(c), cage + 3 * size_t(c) + 3, writtenCage_.begin() + 3 * size_t(c));
      if (!normalsStale_) pendingRows_.insert(pendingRows_.end(), rows_.begin(), rows_.end());
      if (pendingRows_.size() > vertexCount_ / 8) normalsStale_ = true, pendingRows_.clear();
      ++writes_;
      if (withNormals) writeTableNormals();
      return;
    }
    table_->apply(base_.data(), delta_.data(), origin, relative_.data(), positions_.data(), order_.data());
  }
  writtenCage_.assign(cage, cage + cage3);
  positionsRange_[0] = 0, positionsRange_[1] = uint32_t(vertexCount_);
  ++writes_;
  normalsStale_ = true;
  pendingRows_.clear();
  if (withNormals) writeTableNormals();
}

void SurfaceBuffers::writeTableNormals() {
  if (normalsStale_) gatherNormals();
  else if (!pendingRows_.empty()) gatherSomeNormals(pendingRows_);
  normalsStale_ = false;
  pendingRows_.clear();
}

void SurfaceBuffers::update(const double* fine, Vec3 origin, uint64_t version, const FinePositions::Changes& changes,
                            bool withNormals) {
  if (ringStart_.empty()) buildRing();
  merge(pendingPositions_, changes);
  merge(pendingNormals_, changes);
  const size_t n = vertexCount_;
  if (pendingPositions_.whole || pendingPositions_.vertices.size() > n / 8) pendingPositions_ = FinePositions::Changes{};
  if (pendingNormals_.whole || pendingNormals_.vertices.size() > n / 8) pendingNormals_ = FinePositions::Changes{};
  if (positionsOf_ != version + 1) {
    writePositions(fine, origin);
    positionsOf_ = version + 1;
    ++writes_;
  }
  pendingPositions_ = FinePositions::Changes{false, {}};
  if (withNormals && normalsOf_ != version + 1) {
    if (pendingNormals_.whole || !normalsWritten_) writeNormals(fine);
    else writeSomeNormals(fine);
    normalsWritten_ = true;
    normalsOf_ = version + 1;
    pendingNormals_ = FinePositions::Changes{false, {}};
  }
}

void SurfaceBuffers::writePositions(const double* fine, Vec3 o) {
  float* out = positions_.data();
  const size_t n = vertexCount_;
  const uint32_t* caller = hierarchy_->inputIndex.data();
  if (!pendingPositions_.whole) {  // the vertices the stencils touched
    uint32_t first = UINT32_MAX, end = 0;
    for (uint32_t h : pendingPositions_.vertices) {
      const uint32_t v = caller[h];
      float* p = out + 3 * size_t(v);
      p[0] = float(fine[3 * size_t(h)] + o.x), p[1] = float(fine[3 * size_t(h) + 1] + o.y), p[2] = float(fine[3 * size_t(h) + 2] + o.z);
      first = std::min(first, v), end = std::max(end, v + 1);
    }
    positionsRange_[0] = first == UINT32_MAX ? 0 : first, positionsRange_[1] = end;
    return;
  }
  positionsRange_[0] = 0, positionsRange_[1] = uint32_t(n);
  // Every whole pass below writes each vertex's own entries: blocks of vertices on the pool's threads.
  if (callerIsHierarchyOrder_) {
    parallelFor(0, n, kVerticesPerBlock, [&](size_t first, size_t end) {
      for (size_t i = first; i < end; ++i) {  // contiguous: the compiler vectorizes it
        out[3 * i] = float(fine[3 * i] + o.x);
        out[3 * i + 1] = float(fine[3 * i + 1] + o.y);
        out[3 * i + 2] = float(fine[3 * i + 2] + o.z);
      }
    });
    return;
  }
  parallelFor(0, n, kVerticesPerBlock, [&](size_t first, size_t end) {
    for (size_t h = first; h < end; ++h) {
      float* p = out + 3 * size_t(caller[h]);
      p[0] = float(fine[3 * h] + o.x), p[1] = float(fine[3 * h + 1] + o.y), p[2] = float(fine[3 * h + 2] + o.z);
    }
  });
}

void SurfaceBuffers::writeRelative(const double* fine) {
  // Relative to the reference point (inside the mesh): no cancellation in float.
  const size_t n = vertexCount_;
  const uint32_t* caller = hierarchy_->inputIndex.data();
  relative_.resize(4 * n);
  float* r = relative_.data();
  const uint32_t* slot = slot_.data();
  parallelFor(0, n, kVerticesPerBlock, [&](size_t first, size_t end) {
    for (size_t h = first; h < end; ++h) {
      float* p = r + 4 * size_t(slot[caller[h]]);
      p[0] = float(fine[3 * h]), p[1] = float(fine[3 * h + 1]), p[2] = float(fine[3 * h + 2]), p[3] = 0.0f;
    }
  });
}

void SurfaceBuffers::buildRing() {
  const size_t n = vertexCount_;
  const uint32_t* caller = hierarchy_->inputIndex.data();
  const std::vector<uint32_t>& faces = hierarchy_->fineFaces();
  // First the pairs, by vertex (CSR), then each closed fan (every vertex of a closed manifold mesh)
  // chained into its ring of neighbors, so that each neighbor is read once.
  std::vector<uint32_t> start(n + 1, 0);
  for (uint32_t h : faces) ++start[caller[h] + 1];
  for (size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<uint32_t> pairs(2 * faces.size()), next(start.begin(), start.end() - 1);
  for (size_t t = 0; t < faces.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = caller[faces[t + k]];
      uint32_t* pair = &pairs[2 * size_t(next[v]++)];
      pair[0] = caller[faces[t + (k + 1) % 3]], pair[1] = caller[faces[t + (k + 2) % 3]];
    }
  next = {};
  ringStart_.assign(n + 1, 0);
  closedRing_.assign(n, 0);
  ring_.clear();
  ring_.reserve(faces.size() + faces.size() / 8);
  std::vector<uint32_t> chain;
  std::vector<uint8_t> used;
  for (size_t v = 0; v < n; ++v) {
    const uint32_t* p = &pairs[2 * size_t(start[v])];
    const size_t k = start[v + 1] - start[v];
    chain.clear();
    used.assign(k, 0);
    bool closed = false;
    if (k >= 3) {  // follow b of one face to the face whose a it is, back to the first a
      chain.push_back(p[0]), used[0] = 1;
      uint32_t b = p[1];
      for (size_t step = 1; step < k; ++step) {
        size_t found = k;
        for (size_t j = 0; j < k && found == k; ++j)
          if (!used[j] && p[2 * j] == b) found = j;
        if (found == k) break;
        chain.push_back(b), used[found] = 1, b = p[2 * found + 1];
      }
      closed = chain.size() == k && b == p[0];
    }
    if (closed) {
      ring_.insert(ring_.end(), chain.begin(), chain.end());
      closedRing_[v] = 1;
    } else {
      ring_.insert(ring_.end(), p, p + 2 * k);
    }
    ringStart_[v + 1] = uint32_t(ring_.size());
  }
  layOut();
}

void SurfaceBuffers::layOut() {
  // The caller's order when it is local already (most files: each vertex's neighbours near it, and
  // then the output buffers are written in order too); else a breadth-first order over the ring's
  // neighbours, each component from its first vertex: a vertex's neighbours sit within about two
  // fronts of it (a few thousand vertices on a million-vertex closed surface), whatever the caller's
  // order (a hierarchy's order puts most neighbours a megabyte away).
  const size_t n = vertexCount_;
  const size_t near = std::max<size_t>(64, n / 64);
  size_t far = 0;
  for (uint32_t v = 0; v < n; ++v)
    for (uint32_t k = ringStart_[v]; k < ringStart_[v + 1]; ++k) far += (ring_[k] > v ? ring_[k] - v : v - ring_[k]) > near;
  order_.clear();
  inCallerOrder_ = far * 10 < ring_.size();
  if (inCallerOrder_) {
    order_.resize(n);
    for (uint32_t v = 0; v < n; ++v) order_[v] = v;
    slot_ = order_;
    return;
  }
  order_.reserve(n);
  slot_.assign(n, UINT32_MAX);
  for (uint32_t seed = 0; seed < n; ++seed) {
    if (slot_[seed] != UINT32_MAX) continue;
    size_t head = order_.size();
    slot_[seed] = uint32_t(order_.size()), order_.push_back(seed);
    for (; head < order_.size(); ++head) {
      const uint32_t v = order_[head];
      for (uint32_t k = ringStart_[v]; k < ringStart_[v + 1]; ++k) {
        const uint32_t w = ring_[k];
        if (slot_[w] == UINT32_MAX) slot_[w] = uint32_t(order_.size()), order_.push_back(w);
      }
    }
  }
  // The rings in that order, naming neighbours by their slots.
  std::vector<uint32_t> start(n + 1, 0), ring(ring_.size());
  std::vector<uint8_t> closed(n);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t v = order_[i];
    start[i + 1] = start[i] + (ringStart_[v + 1] - ringStart_[v]);
    closed[i] = closedRing_[v];
    for (uint32_t k = ringStart_[v], at = start[i]; k < ringStart_[v + 1]; ++k, ++at) ring[at] = slot_[ring_[k]];
  }
  ringStart_ = std::move(start), ring_ = std::move(ring), closedRing_ = std::move(closed);
}

namespace {

// The area-weighted unit normal of v (a vertex of no area keeps zero, as three.js's
// computeVertexNormals leaves it), written at out (3 floats and one more, overwritten later or
// spare): the sum of the cross products (a - v) x (b - v) of its faces (v, a, b), from its ring of
// neighbors when its fan is closed (face i: neighbors i, i + 1), else from its pairs a, b.
#ifdef __wasm_simd128__
// cross(a, b) = yzx(a * yzx(b) - yzx(a) * b): the outer shuffle is taken once for the whole sum.
inline v128_t yzx(v128_t a) { return wasm_i32x4_shuffle(a, a, 1, 2, 0, 3); }
inline void vertexNormal(const float* r, const uint32_t* ring, const uint32_t* ringEnd, bool closed, size_t v, float* out) {
  const v128_t p = wasm_v128_load(r + 4 * v);
  v128_t sum = wasm_f32x4_splat(0.0f);
  if (closed) {
    const v128_t u0 = wasm_f32x4_sub(wasm_v128_load(r + 4 * size_t(ring[0])), p), s0 = yzx(u0);
    v128_t u = u0, s = s0;
    for (const uint32_t* q = ring + 1; q != ringEnd; ++q) {
      const v128_t w = wasm_f32x4_sub(wasm_v128_load(r + 4 * size_t(*q)), p), t = yzx(w);
      sum = wasm_f32x4_add(sum, wasm_f32x4_sub(wasm_f32x4_mul(u, t), wasm_f32x4_mul(s, w)));
      u = w, s = t;
    }
    sum = wasm_f32x4_add(sum, wasm_f32x4_sub(wasm_f32x4_mul(u, s0), wasm_f32x4_mul(s, u0)));
  } else {
    for (const uint32_t* q = ring; q != ringEnd; q += 2) {
      const v128_t u = wasm_f32x4_sub(wasm_v128_load(r + 4 * size_t(q[0])), p);
      const v128_t w = wasm_f32x4_sub(wasm_v128_load(r + 4 * size_t(q[1])), p);
      sum = wasm_f32x4_add(sum, wasm_f32x4_sub(wasm_f32x4_mul(u, yzx(w)), wasm_f32x4_mul(yzx(u), w)));
    }
  }
  sum = yzx(sum);
  const v128_t squares = wasm_f32x4_mul(sum, sum);
  const float length = std::sqrt(wasm_f32x4_extract_lane(squares, 0) + wasm_f32x4_extract_lane(squares, 1) +
                                 wasm_f32x4_extract_lane(squares, 2));
  wasm_v128_store(out, wasm_f32x4_mul(sum, wasm_f32x4_splat(length > 0.0f ? 1.0f / length : 0.0f)));
}
#else
inline void addCross(const float* r, const float* p, uint32_t a, uint32_t b, float* s) {
  const float* x = r + 4 * size_t(a);
  const float* y = r + 4 * size_t(b);
  const float ux = x[0] - p[0], uy = x[1] - p[1], uz = x[2] - p[2];
  const float wx = y[0] - p[0], wy = y[1] - p[1], wz = y[2] - p[2];
  s[0] += uy * wz - uz * wy, s[1] += uz * wx - ux * wz, s[2] += ux * wy - uy * wx;
}
inline void vertexNormal(const float* r, const uint32_t* ring, const uint32_t* ringEnd, bool closed, size_t v, float* out) {
  const float* p = r + 4 * v;
  float s[3] = {0, 0, 0};
  if (closed) {
    for (const uint32_t* q = ring; q + 1 != ringEnd; ++q) addCross(r, p, q[0], q[1], s);
    addCross(r, p, ringEnd[-1], ring[0], s);
  } else {
    for (const uint32_t* q = ring; q != ringEnd; q += 2) addCross(r, p, q[0], q[1], s);
  }
  const float length = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  const float scale = length > 0.0f ? 1.0f / length : 0.0f;
  out[0] = s[0] * scale, out[1] = s[1] * scale, out[2] = s[2] * scale;
}
#endif

}  // namespace

void SurfaceBuffers::gatherNormals() {
  const size_t n = vertexCount_;
  const float* r = relative_.data();
  const uint32_t* start = ringStart_.data();
  const uint32_t* ring = ring_.data();
  float* out = normals_.data();
  const uint8_t* closed = closedRing_.data();
  const uint32_t* order = order_.data();
  // Each vertex gathers its own normal from its ring (no sums across vertices): blocks on the pool's threads.
  parallelFor(0, n, kVerticesPerBlock, [&](size_t first, size_t end) {
    for (size_t i = first; i < end; ++i) {
      float normal[4];
      vertexNormal(r, ring + start[i], ring + start[i + 1], closed[i], i, normal);
      std::memcpy(out + 3 * size_t(order[i]), normal, 3 * sizeof(float));
    }
  });
  normalsRange_[0] = 0, normalsRange_[1] = uint32_t(n);
}

void SurfaceBuffers::writeSomeNormals(const double* fine) {
  const uint32_t* caller = hierarchy_->inputIndex.data();
  // The moved vertices' relative positions, then the normals around them.
  float* r = relative_.data();
  rows_.clear();
  for (uint32_t h : pendingNormals_.vertices) {
    const uint32_t i = slot_[caller[h]];
    float* p = r + 4 * size_t(i);
    p[0] = float(fine[3 * size_t(h)]), p[1] = float(fine[3 * size_t(h) + 1]), p[2] = float(fine[3 * size_t(h) + 2]);
    rows_.push_back(i);
  }
  gatherSomeNormals(rows_);
}

void SurfaceBuffers::gatherSomeNormals(const std::vector<uint32_t>& moved) {
  if (++markRound_ == 0) std::fill(mark_.begin(), mark_.end(), 0), markRound_ = 1;
  // The moved vertices and every vertex of a face around them are affected.
  affected_.clear();
  for (uint32_t v : moved) {
    if (mark_[v] != markRound_) mark_[v] = markRound_, affected_.push_back(v);
    for (uint32_t k = ringStart_[v]; k < ringStart_[v + 1]; ++k) {
      const uint32_t w = ring_[k];
      if (mark_[w] != markRound_) mark_[w] = markRound_, affected_.push_back(w);
    }
  }
  uint32_t first = UINT32_MAX, end = 0;
  const float* r = relative_.data();
  float* out = normals_.data();
  for (uint32_t i : affected_) {
    float normal[4];
    vertexNormal(r, ring_.data() + ringStart_[i], ring_.data() + ringStart_[i + 1], closedRing_[i], i, normal);
    const uint32_t v = order_[i];
    std::copy(normal, normal + 3, out + 3 * size_t(v));
    first = std::min(first, v), end = std::max(end, v + 1);
  }
  normalsRange_[0] = first == UINT32_MAX ? 0 : first, normalsRange_[1] = end;
}

void SurfaceBuffers::writeNormals(const double* fine) {
  writeRelative(fine);
  gatherNormals();
}

}  // namespace mrvol
