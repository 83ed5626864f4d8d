// embind layer for quad meshes and the Catmull-Clark scheme (mrvol/quad_*.h): converts types,
// nothing else. Like io_bindings.cpp, a core error never crosses as an exception: it is kept here
// and lib/quad.mjs takes it with _takeQuadError() and throws MrvolError. Theta objects are the
// same _Theta class bindings.cpp registers.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "mrvol/error.h"
#include "mrvol/quad_editor.h"
#include "mrvol/quad_multires_mesh.h"
#include "mrvol/quad_obj.h"
#include "edit_options.h"
#include "guard.h"
#include "mesh_info.h"
#include "typed_arrays.h"

using emscripten::val;
using namespace mrvol;
using namespace mrvol::bindings;

namespace {

ErrorSlot quadErrors("the input");

template <class F>
auto guarded(F&& f) -> decltype(f()) { return quadErrors.guarded(std::forward<F>(f)); }

val takeQuadError() { return quadErrors.take(); }

QuadMesh quadMesh(const val& positions, const val& quads) {
  return QuadMesh{toVector<double>(positions, "positions"), toVector<uint32_t>(quads, "quads")};
}

std::string textOf(const val& bytes) {
  if (!bytes.instanceof(val::global("Uint8Array"))) throw Error("the OBJ file must be a Uint8Array");
  std::string text(bytes["length"].as<size_t>(), '\0');
  val(emscripten::typed_memory_view(text.size(), reinterpret_cast<uint8_t*>(text.data()))).call<void>("set", bytes);
  return text;
}

val q_readObjQuads(val bytes) {
  return guarded([&] {
    QuadMesh m = readObjQuads(textOf(bytes));
    val out = val::object();
    out.set("positions", toTyped(m.positions));
    out.set("quads", toTyped(m.quads));
    return out;
  });
}
// OBJ text as a Uint8Array (lib/quad.mjs decodes it), as js_writeObj.
val q_writeObjQuads(val positions, val quads) {
  return guarded([&] {
    const std::string out = writeObjQuads(quadMesh(positions, quads));
    return val(emscripten::typed_memory_view(out.size(), reinterpret_cast<const uint8_t*>(out.data()))).call<val>("slice");
  });
}
val q_volume(val positions, val quads) {
  return guarded([&] {
    QuadMesh m = quadMesh(positions, quads);
    validateQuadMesh(m);
    return val(bilinearVolume(m));
  });
}

QuadMultiresMesh* q_open(val positions, val quads, int maxLevels) {
  return guarded([&] { return new QuadMultiresMesh(quadMesh(positions, quads), maxLevels); });
}
QuadMultiresMesh* q_subdivide(val positions, val quads, int levels) {
  return guarded([&] { return new QuadMultiresMesh(QuadMultiresMesh::subdivide(quadMesh(positions, quads), levels)); });
}
val q_subdivisionPositions(const QuadMultiresMesh& m, val base) {
  return guarded([&] { return toTyped(m.subdivisionPositions(toVector<double>(base, "base positions"))); });
}
val q_info(const QuadMultiresMesh& m, val positions) {
  return guarded([&] {
    val out = meshInfoToJs(m.info(toVector<double>(positions, "positions")));
    out.set("lowestLevel", m.lowestLevel());
    return out;
  });
}
val q_quads(const QuadMultiresMesh& m) { return guarded([&] { return toTyped(m.quads()); }); }
val q_levelQuads(const QuadMultiresMesh& m, int level) { return guarded([&] { return toTyped(m.levelQuads(level)); }); }
val q_depths(const QuadMultiresMesh& m) { return guarded([&] { return depthsToJs(m.hierarchy().h); }); }
val q_analyze(const QuadMultiresMesh& m, val p, int level) {
  return guarded([&] { return toTyped(m.analyze(toVector<double>(p, "positions"), level)); });
}
val q_synthesize(const QuadMultiresMesh& m, val c, int level) {
  return guarded([&] { return toTyped(m.synthesize(toVector<double>(c, "coefficients"), level)); });
}
val q_roundtripError(const QuadMultiresMesh& m, val p, int level) {
  return guarded([&] { return val(m.roundtripError(toVector<double>(p, "positions"), level)); });
}
val q_liftingSteps(const QuadMultiresMesh& m, int level) {
  return guarded([&] {
    val out = val::array();
    for (const LiftingStep& step : m.liftingSteps(level)) {
      val s = val::object();
      s.set("name", step.name);
      s.set("scaling", step.scaling);
      s.set("readsOnlyDetails", step.readsOnlyDetails);
      s.set("targets", toTyped(step.targets));
      s.set("offsets", toTyped(step.offsets));
      s.set("sources", toTyped(step.sources));
      s.set("weights", toTyped(step.weights));
      out.call<void>("push", s);
    }
    return out;
  });
}
Theta* q_computeTheta(const QuadMultiresMesh& m, int level, std::string storage) {
  return guarded([&]() -> Theta* {
    if (storage != "cage" && storage != "full") throw Error("unknown tensor storage '" + storage + "' (expected cage or full)");
    auto theta = std::make_unique<Theta>();
    theta->tensor = m.computeTensor(level, storage == "full" ? TensorStorage::Full : TensorStorage::Cage);
    theta->header = m.thetaHeader(theta->tensor);
    return theta.release();
  });
}
val q_thetaVolume(const QuadMultiresMesh& m, const Theta& t, int level, val positions) {
  return guarded([&] {
    m.checkTheta(t.header, level);
    return val(m.tensorVolume(t.tensor, toVector<double>(positions, "positions")));
  });
}
val q_fingerprint(const QuadMultiresMesh& m) {
  return guarded([&] {
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(m.fingerprint()));
    return val(std::string(hex));
  });
}

QuadVolumeEditor* q_createEditor(const QuadMultiresMesh& m, int level, val positions) {
  return guarded([&]() -> QuadVolumeEditor* {
    const std::vector<double> p = toVector<double>(positions, "positions");
    m.checkPositions(p);
    if (level >= 0 && level < m.lowestLevel())
      throw Error("analysis cannot reach level " + std::to_string(level) +
                  ": the base is a cube, whose first Catmull-Clark split is not invertible (edit at level 1 or above)");
    return new QuadVolumeEditor(m.hierarchy(), m.transform(), level, p.data());
  });
}
bool q_editorUseTheta(QuadVolumeEditor& e, const QuadMultiresMesh& m, const Theta& t) {
  return guarded([&] {
    m.checkTheta(t.header, e.level());
    e.useTensor(t.tensor);
    return true;
  });
}
bool q_editorUseMatrixFree(QuadVolumeEditor& e) { return guarded([&] { return e.useMatrixFree(), true; }); }
val q_editorPath(const QuadVolumeEditor& e) { return guarded([&] { return val(std::string(gradientPathName(e.path()))); }); }
bool q_editorUsePolynomial(QuadVolumeEditor& e) { return guarded([&] { return e.usePolynomial(); }); }
bool q_editorSetAllFree(QuadVolumeEditor& e, bool all) { return guarded([&] { return e.setAllFree(all), true; }); }
bool q_editorSetFreeSet(QuadVolumeEditor& e, std::string mode, val list, val detailLevels) {
  return guarded([&] {
    std::vector<int> levels = detailLevels.isUndefined() ? std::vector<int>{} : toVector<int>(detailLevels, "detail levels");
    const FreeCage cage = freeCageMode(mode);
    e.setFreeSet(cage, cage == FreeCage::List ? toVector<uint32_t>(list, "free set") : std::vector<uint32_t>{}, levels);
    return true;
  });
}
val q_editorGradient(const QuadVolumeEditor& e, std::string path) {
  return guarded([&] {
    std::vector<double> g;
    if (path == "tensor" || path == "polynomial") e.gradientPolynomial(g);
    else if (path == "matrix-free") e.gradientMatrixFree(g);
    else throw Error("unknown gradient path '" + path + "' (tensor, polynomial or matrix-free)");
    return toTyped(g);
  });
}
// The centre of mass of the bilinear patches, kept with the volume (CageEditor::keepCentroid).
bool q_editorKeepCentroid(QuadVolumeEditor& e, bool keep) { return guarded([&] { return e.keepCentroid(keep), true; }); }
val q_vec3(Vec3 v) { return toTyped(std::vector<double>{v.x, v.y, v.z}); }
val q_editorCentroid(const QuadVolumeEditor& e) { return guarded([&] { return q_vec3(e.centroid()); }); }
val q_editorReferenceCentroid(const QuadVolumeEditor& e) { return guarded([&] { return q_vec3(e.referenceCentroid()); }); }
val q_editorCageVertices(const QuadVolumeEditor& e) { return guarded([&] { return toTyped(e.cageVertices()); }); }
val q_editorCageIndexOf(const QuadVolumeEditor& e, double v) {
  return guarded([&] {
    if (!(v >= 0) || v != std::floor(v) || v > 4294967295.0) throw Error("vertex index must be a non-negative integer");
    return val(double(e.cageIndexOf(uint32_t(v))));
  });
}
val q_editorCagePositions(const QuadVolumeEditor& e) { return guarded([&] { return toTyped(e.cagePositions()); }); }
val q_editorPositions(const QuadVolumeEditor& e) { return guarded([&] { return toTyped(e.positions()); }); }
val q_editorVolume(const QuadVolumeEditor& e) { return guarded([&] { return val(e.volume()); }); }
val q_editorReference(const QuadVolumeEditor& e) { return guarded([&] { return val(e.referenceVolume()); }); }
bool q_editorSetReference(QuadVolumeEditor& e, double v) { return guarded([&] { return e.setReferenceVolume(v), true; }); }
val q_editorCoefficients(const QuadVolumeEditor& e) { return guarded([&] { return toTyped(e.coefficients()); }); }

val q_editorDeformCage(QuadVolumeEditor& e, val target, val held, val options) {
  return guarded([&] {
    return reportToJs(e.deformCage(toVector<double>(target, "cage target"), toVector<uint8_t>(held, "held flags"),
                                 toEditOptions(options)));
  });
}
val q_editorCorrect(QuadVolumeEditor& e, val held, val options) {
  return guarded([&] { return reportToJs(e.correct(toVector<uint8_t>(held, "held flags"), toEditOptions(options))); });
}

}  // namespace

// All guarded but the getters of a field (levels, lowestLevel, level, cageSize, keepsCentroid) and
// _takeQuadError: they neither allocate nor throw.
EMSCRIPTEN_BINDINGS(mrvol_quad) {
  using namespace emscripten;
  function("_takeQuadError", &takeQuadError);
  function("_readObjQuads", &q_readObjQuads);
  function("_writeObjQuads", &q_writeObjQuads);
  function("_quadVolume", &q_volume);
  function("_openQuadMesh", &q_open, allow_raw_pointers());
  function("_subdivideQuads", &q_subdivide, allow_raw_pointers());
  class_<QuadMultiresMesh>("_QuadMultiresMesh")
      .function("levels", &QuadMultiresMesh::levels)
      .function("lowestLevel", &QuadMultiresMesh::lowestLevel)
      .function("info", &q_info)
      .function("quads", &q_quads)
      .function("levelQuads", &q_levelQuads)
      .function("depths", &q_depths)
      .function("subdivisionPositions", &q_subdivisionPositions)
      .function("analyze", &q_analyze)
      .function("synthesize", &q_synthesize)
      .function("roundtripError", &q_roundtripError)
      .function("liftingSteps", &q_liftingSteps)
      .function("computeTheta", &q_computeTheta, allow_raw_pointers())
      .function("thetaVolume", &q_thetaVolume)
      .function("fingerprint", &q_fingerprint)
      .function("createEditor", &q_createEditor, allow_raw_pointers());
  class_<QuadVolumeEditor>("_QuadVolumeEditor")
      // CageEditor members as this class's: embind takes member pointers of the bound class only
      .function("level", static_cast<int (QuadVolumeEditor::*)() const>(&QuadVolumeEditor::level))
      .function("cageSize", static_cast<uint32_t (QuadVolumeEditor::*)() const>(&QuadVolumeEditor::cageSize))
      .function("useTheta", &q_editorUseTheta)
      .function("usePolynomial", &q_editorUsePolynomial)
      .function("useMatrixFree", &q_editorUseMatrixFree)
      .function("setAllFree", &q_editorSetAllFree)
      .function("setFreeSet", &q_editorSetFreeSet)
      .function("gradient", &q_editorGradient)
      .function("path", &q_editorPath)
      .function("cageVertices", &q_editorCageVertices)
      .function("cageIndexOf", &q_editorCageIndexOf)
      .function("cagePositions", &q_editorCagePositions)
      .function("positions", &q_editorPositions)
      .function("volume", &q_editorVolume)
      .function("referenceVolume", &q_editorReference)
      .function("setReferenceVolume", &q_editorSetReference)
      .function("coefficients", &q_editorCoefficients)
      .function("keepCentroid", &q_editorKeepCentroid)
      .function("keepsCentroid", static_cast<bool (QuadVolumeEditor::*)() const>(&QuadVolumeEditor::keepsCentroid))
      .function("centroid", &q_editorCentroid)
      .function("referenceCentroid", &q_editorReferenceCentroid)
      .function("deformCage", &q_editorDeformCage)
      .function("correct", &q_editorCorrect);
}
