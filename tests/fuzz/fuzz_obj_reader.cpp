// libFuzzer target: arbitrary bytes through the whole input path of the core.
//
//   bytes -> ObjReader in small chunks == readObj (differential) ->
//   readObj (with lines and extras; writeObjLike gives the bytes back) -> validateMesh (differential: reference_mesh.h) -> MultiresMesh (hierarchy detection) -> Loop analysis and
//   synthesis at every level (then Butterfly and linear), plus writeObj -> readObj (text round
//   trip) and the mesh volume.
//
// The core reports every failure as mrvol::Error; std::bad_alloc is tolerated for absurd sizes.
// Any other exception escapes and aborts, so libFuzzer reports it. Broken invariants call
// __builtin_trap().
//
//   build/fuzz/fuzz_obj_reader build/fuzz/corpus-fuzz_obj_reader -dict=tests/fuzz/obj.dict
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/mesh.h"
#include "mrvol/multires_mesh.h"
#include "mrvol/obj_reader.h"
#include "reference_mesh.h"

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

double maxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::fmax(m, std::fabs(x));
  return m;
}

// Perfect reconstruction of the Loop transform on the file's own positions, at every level. The
// steps invert exactly in exact arithmetic, so the error is rounding only: relative to the
// coordinate magnitude, amplified by at most 1/K(3) = 10 per analysis level (the N step), which
// 1e-9 leaves room for up to 16 levels of typical meshes. The absolute floor covers subnormals.
void checkRoundtrip(const mrvol::MultiresMesh& mesh, const std::vector<double>& x, mrvol::SchemeKind kind) {
  mrvol::SchemeOptions scheme;  // default Loop alpha and beta
  scheme.kind = kind;
  const double scale = maxAbs(x);
  const double tolerance = 1e-9 * scale + 1e-300;
  for (int level = 0; level <= mesh.levels(); ++level) {
    std::vector<double> coefficients = mesh.analyze(x, level, scheme);
    for (double c : coefficients) check(std::isfinite(c));
    std::vector<double> back = mesh.synthesize(coefficients, level, scheme);
    check(back.size() == x.size());
    double err = 0;
    for (size_t i = 0; i < x.size(); ++i) err = std::fmax(err, std::fabs(back[i] - x[i]));
    check(err <= tolerance);
  }
  check(mesh.roundtripError(x, 0, scheme) <= tolerance);
}

void checkHierarchyShape(const mrvol::MultiresMesh& mesh) {
  const mrvol::Hierarchy& h = mesh.hierarchy();
  const size_t nv = mesh.vertexCount();
  check(h.levels >= 0 && h.levels <= 16);
  check(h.vertexCount.size() == size_t(h.levels) + 1 && h.faces.size() == size_t(h.levels) + 1);
  check(h.fineVertexCount() == nv);
  check(h.fineFaces().size() == mesh.faces().size());
  check(h.inputIndex.size() == nv && h.hierarchyIndex.size() == nv);
  for (size_t v = 0; v < nv; ++v) check(h.inputIndex[h.hierarchyIndex[v]] == v);
  for (int l = 1; l <= h.levels; ++l) {
    check(h.vertexCount[l] > h.vertexCount[l - 1]);
    check(h.faces[l].size() == 4 * h.faces[l - 1].size());
  }
}

void run(std::string_view text) {
  mrvol::SourceLines lines;
  mrvol::ObjExtras extras;
  mrvol::TriangleMesh mesh = mrvol::readObj(text, &lines, &extras);
  check(lines.vertex.size() == mesh.vertexCount() && lines.face.size() == mesh.faceCount());
  // Attributes are consistent with what was read: one per triangle corner, pointing into the file's.
  constexpr uint32_t kNoIndex = mrvol::ObjExtras::kNoIndex;
  check(extras.cornerTexCoords.empty() || extras.cornerTexCoords.size() == mesh.faces.size());
  check(extras.cornerNormals.empty() || extras.cornerNormals.size() == mesh.faces.size());
  for (uint32_t t : extras.cornerTexCoords) check(t == kNoIndex || t < extras.texCoords.size() / 2);
  for (uint32_t n : extras.cornerNormals) check(n == kNoIndex || n < extras.normals.size() / 3);
  check(extras.colors.empty() || extras.colors.size() == mesh.positions.size());
  check(extras.polygonTriangles <= mesh.faceCount());
  // With its own positions, writeObjLike gives the file back byte for byte (every coordinate
  // reads back as the value it holds, so none is respelled).
  check(mrvol::writeObjLike(text, mesh.positions.data(), mesh.vertexCount()) == text);
  // Welded as the readers users call weld it (weldObjVertices): each face's corners stay distinct,
  // lines and colours one per vertex, and writeObjLike of the welded positions gives the file back
  // too (each v line gets its own position: those of a vertex are equal).
  {
    mrvol::TriangleMesh welded = mesh;
    mrvol::SourceLines weldedLines = lines;
    mrvol::ObjExtras weldedExtras = extras;
    std::vector<uint32_t> first;
    const size_t merged = mrvol::weldObjVertices(welded, &weldedLines, &weldedExtras, &first);
    check(welded.vertexCount() + merged == mesh.vertexCount() && welded.faces.size() == mesh.faces.size());
    check(weldedLines.vertex.size() == welded.vertexCount() && first.size() == welded.vertexCount());
    check(weldedExtras.colors.empty() || weldedExtras.colors.size() == welded.positions.size());
    for (size_t v = 0; v < first.size(); ++v) {
      check(first[v] < mesh.vertexCount() && weldedLines.vertex[v] == lines.vertex[first[v]]);
      for (int k = 0; k < 3; ++k) check(welded.positions[3 * v + k] == mesh.positions[3 * size_t(first[v]) + k]);
    }
    for (size_t i = 0; i < welded.faces.size(); ++i) check(welded.faces[i] < welded.vertexCount());
    if (merged > 0) {
      for (size_t f = 0; f < welded.faceCount(); ++f) {
        const uint32_t* c = &welded.faces[3 * f];
        check(c[0] != c[1] && c[1] != c[2] && c[0] != c[2]);
      }
      std::string back = mrvol::writeObjLike(text, welded.positions.data(), welded.vertexCount());
      // -0 and +0 weld: the first's sign is written into the others' lines (the only respelling).
      mrvol::TriangleMesh reread = mrvol::readObj(back);
      check(reread.faces == mesh.faces && reread.positions == mesh.positions);
    }
  }
  // What readObj returns is well formed even when it is no valid mesh.
  check(mesh.positions.size() % 3 == 0 && mesh.faces.size() % 3 == 0 && !mesh.faces.empty());
  for (uint32_t i : mesh.faces) check(i < mesh.vertexCount());
  for (double x : mesh.positions) check(std::isfinite(x) && std::fabs(x) <= 1e100);

  // Writing and reading back gives the same mesh exactly (17 significant digits).
  mrvol::TriangleMesh again = mrvol::readObj(mrvol::writeObj(mesh));
  check(again.faces == mesh.faces);
  check(again.positions.size() == mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) check(again.positions[i] == mesh.positions[i]);

  // validateMesh against the plain reference implementation: same verdict, same counts.
  const reference::Topology expected = reference::validate(mesh);
  mrvol::MeshTopology topology;
  try {
    topology = mrvol::validateMesh(mesh);
  } catch (const mrvol::Error&) {
    check(!expected.valid);
    throw;
  }
  check(expected.valid);
  check(topology.edges == expected.edges && topology.boundaryEdges == expected.boundaryEdges &&
        topology.components == expected.components);
  check(topology.closed == (topology.boundaryEdges == 0));
  // Euler: V - E + F = 2 C - 2 g - (boundary loops) for a single closed component.
  if (topology.closed && topology.components == 1)
    check(long(mesh.vertexCount()) - long(topology.edges) + long(mesh.faceCount()) == 2 - 2 * topology.genus);

  mrvol::MultiresMesh multires(mesh);
  checkHierarchyShape(multires);
  mrvol::MeshInfo info = multires.info(mesh.positions);
  check(std::isfinite(info.volume));  // |x| <= 1e100 keeps the triple products finite
  check(info.levels == multires.levels() && info.baseVertices == multires.hierarchy().vertexCount[0]);
  if (multires.levels() > 0) {
    checkRoundtrip(multires, mesh.positions, mrvol::SchemeKind::Loop);
    // The interpolating schemes have their own stencils on the same hierarchy (extraordinary and
    // boundary vertices, Butterfly's integral-based update weights): they must reconstruct too.
    checkRoundtrip(multires, mesh.positions, mrvol::SchemeKind::Butterfly);
    checkRoundtrip(multires, mesh.positions, mrvol::SchemeKind::Linear);
  }
}

}  // namespace

// The chunked reader (obj_reader.h) against readObj: chunks of 1 to 16 bytes (from the input's
// first byte) must give the same mesh and lines, or the same error.
void checkChunkedRead(std::string_view text) {
  std::string wholeError, chunkedError;
  mrvol::TriangleMesh whole, chunked;
  mrvol::SourceLines wholeLines, chunkedLines;
  try {
    whole = mrvol::readObj(text, &wholeLines);
  } catch (const mrvol::Error& e) {
    wholeError = e.what();
  }
  try {
    mrvol::ObjReader reader(text.size());
    const size_t step = text.empty() ? 1 : 1 + static_cast<unsigned char>(text[0]) % 16;
    for (size_t at = 0; at < text.size(); at += step) reader.feed(text.substr(at, step));
    chunked = reader.finish(&chunkedLines);
  } catch (const mrvol::Error& e) {
    chunkedError = e.what();
  }
  // The size guard counts differently (whole file first, or chunk by chunk): its message may differ.
  if (wholeError.find("too large to open") != std::string::npos) return;
  check(wholeError == chunkedError);
  check(whole.positions == chunked.positions && whole.faces == chunked.faces);
  check(wholeLines.vertex == chunkedLines.vertex && wholeLines.face == chunkedLines.face);
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    checkChunkedRead(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const std::bad_alloc&) {
  }
  try {
    run(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const mrvol::Error&) {
    // The documented way to refuse an input.
  } catch (const std::bad_alloc&) {
    // Absurd sizes only; ASan's allocator limit (-rss_limit_mb / malloc_limit_mb) reports real blow-ups.
  }
  return 0;
}
