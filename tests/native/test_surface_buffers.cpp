// The renderer's buffers (SurfaceBuffers): float32 positions equal to the editor's positions, and
// area-weighted unit normals equal to a reference summed here in doubles, in the caller's order
// (the same order as the hierarchy, and a shuffled one), after edits; nothing rewritten for a
// version already written.
#include <gtest/gtest.h>

#include <cmath>

#include "fixtures.h"
#include "shuffled_subdivision.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/surface_buffers.h"
#include "mrvol/volume_editor.h"

using namespace mrvol;

namespace {

std::vector<double> referenceNormals(const std::vector<double>& p, const std::vector<uint32_t>& faces) {
  std::vector<double> n(p.size(), 0.0);
  for (size_t t = 0; t < faces.size(); t += 3) {
    const double* a = &p[3 * size_t(faces[t])];
    const double* b = &p[3 * size_t(faces[t + 1])];
    const double* c = &p[3 * size_t(faces[t + 2])];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
    for (int k = 0; k < 3; ++k) n[3 * faces[t + k]] += x, n[3 * faces[t + k] + 1] += y, n[3 * faces[t + k] + 2] += z;
  }
  for (size_t i = 0; i < n.size(); i += 3) {
    const double l = std::sqrt(n[i] * n[i] + n[i + 1] * n[i + 1] + n[i + 2] * n[i + 2]);
    if (l > 0) n[i] /= l, n[i + 1] /= l, n[i + 2] /= l;
  }
  return n;
}

// From the editor (through a CageBasisTable for a small cage) or from its fine positions.
void update(VolumeEditor& editor, SurfaceBuffers& buffers, bool fromEditor) {
  if (fromEditor) return buffers.update(editor, true);
  const double* fine = editor.finePositions().data();
  FinePositions::Changes changes;
  editor.takeFinePositionChanges(changes);
  buffers.update(fine, editor.referencePoint(), editor.finePositionsVersion(), changes, true);
}

void checkBuffers(VolumeEditor& editor, SurfaceBuffers& buffers, const std::vector<uint32_t>& callerFaces, const std::string& where,
                  bool fromEditor) {
  update(editor, buffers, fromEditor);
  const std::vector<double> p = editor.positions();
  ASSERT_EQ(3 * buffers.vertexCount(), p.size());
  const double size = fixtures::maxAbs(p);
  const std::vector<double> n = referenceNormals(p, callerFaces);
  double positionError = 0, normalError = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    positionError = std::max(positionError, std::fabs(buffers.positions()[i] - p[i]) / size);
    normalError = std::max(normalError, std::fabs(buffers.normals()[i] - n[i]));
  }
  EXPECT_LT(positionError, 1e-6) << where;
  EXPECT_LT(normalError, 1e-5) << where;
}

// Drags at `level`: at the finest ones, a move of one vertex without preservation rewrites only the
// vertices of its stencil and the normals around them.
void dragAndCheck(const Hierarchy& h, const std::vector<double>& callerPositions, const std::vector<uint32_t>& callerFaces,
                  const std::string& name, int level, bool fromEditor, int expectCallerOrder = -1) {
  WaveletTransform wt(h, SchemeOptions{});
  VolumeEditor editor(h, wt, level, callerPositions.data());
  editor.usePolynomial();
  SurfaceBuffers buffers(h);
  const std::string at = name + " level " + std::to_string(level) + (fromEditor ? " from the editor" : " from the fine positions");
  checkBuffers(editor, buffers, callerFaces, at + " before edits", fromEditor);
  if (expectCallerOrder >= 0) {
    EXPECT_EQ(buffers.inCallerOrder(), expectCallerOrder == 1) << at;
  }
  std::vector<uint8_t> held(editor.cageSize(), 0);
  for (int drag = 0; drag < 12; ++drag) {
    std::vector<double> target = editor.cagePositions();
    const uint32_t c = uint32_t(drag * 7 + 3) % editor.cageSize();
    if (h.boundary[c]) continue;
    target[3 * c] += 0.05, target[3 * c + 2] -= 0.03;
    std::fill(held.begin(), held.end(), 0), held[c] = 1;
    EditOptions options;
    options.preserve = drag % 3 != 0;  // a few moves of one vertex only (the stencils), the rest corrected
    editor.deformCage(target, held, options);
    checkBuffers(editor, buffers, callerFaces, at + " drag " + std::to_string(drag), fromEditor);

  }
  // The version written already: nothing changes, the count of writes stays.
  const uint64_t writes = buffers.version();
  update(editor, buffers, fromEditor);
  EXPECT_EQ(buffers.version(), writes) << at;
}

}  // namespace

TEST(SurfaceBuffers, FollowTheEditsInTheHierarchyOrder) {
  for (const auto& fx : fixtures::baseFixtures()) {
    const Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    std::vector<double> positions(3 * h.fineVertexCount(), 0.0);
    std::copy(fx.base.positions.begin(), fx.base.positions.end(), positions.begin());
    WaveletTransform(h, SchemeOptions{}).synthesize(positions.data(), 0);
    for (int level : {0, 1, h.levels - 1})
      for (bool fromEditor : {false, true}) dragAndCheck(h, positions, h.fineFaces(), fx.name, level, fromEditor);
  }
}

TEST(SurfaceBuffers, FollowTheEditsInAShuffledOrder) {
  const fixtures::Shuffled shuffled = fixtures::shuffledSubdivision(5);
  const Hierarchy h = Hierarchy::detect(shuffled.mesh);
  bool reordered = false;
  for (size_t v = 0; v < h.inputIndex.size(); ++v) reordered = reordered || h.inputIndex[v] != v;
  ASSERT_TRUE(reordered);
  for (int level : {0, h.levels - 1})
    for (bool fromEditor : {false, true})
      dragAndCheck(h, shuffled.mesh.positions, shuffled.mesh.faces, "shuffled icosahedron", level, fromEditor, 0);
}

// A caller's order that is local already (breadth-first, as many files are): the buffers keep it.
TEST(SurfaceBuffers, KeepALocalCallerOrder) {
  const fixtures::Fixture fx = fixtures::baseFixtures()[0];
  const Hierarchy sub = Hierarchy::subdivide(fx.base, fx.levels);
  std::vector<double> positions(3 * sub.fineVertexCount(), 0.0);
  std::copy(fx.base.positions.begin(), fx.base.positions.end(), positions.begin());
  WaveletTransform(sub, SchemeOptions{}).synthesize(positions.data(), 0);
  const std::vector<uint32_t>& faces = sub.fineFaces();
  const size_t n = sub.fineVertexCount();
  std::vector<std::vector<uint32_t>> neighbours(n);
  for (size_t t = 0; t < faces.size(); t += 3)
    for (int k = 0; k < 3; ++k) neighbours[faces[t + k]].push_back(faces[t + (k + 1) % 3]);
  std::vector<uint32_t> label(n, UINT32_MAX), order{0};
  label[0] = 0;
  for (size_t head = 0; head < order.size(); ++head)
    for (uint32_t w : neighbours[order[head]])
      if (label[w] == UINT32_MAX) label[w] = uint32_t(order.size()), order.push_back(w);
  ASSERT_EQ(order.size(), n);
  TriangleMesh mesh{std::vector<double>(3 * n), {}};
  for (size_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) mesh.positions[3 * label[v] + k] = positions[3 * v + k];
  for (uint32_t v : faces) mesh.faces.push_back(label[v]);
  const Hierarchy h = Hierarchy::detect(mesh);
  for (int level : {0, h.levels - 1})
    for (bool fromEditor : {false, true})
      dragAndCheck(h, mesh.positions, mesh.faces, "breadth-first icosahedron", level, fromEditor, 1);
}
