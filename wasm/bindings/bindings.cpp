// embind layer: converts types between JS and the core, nothing else. Raw names start with `_`;
// lib/api.mjs wraps them in the public API. A core error never crosses as an exception: it is kept
// here and the JS side takes it with _takeError() and throws a named MrvolError.
#include <emscripten/bind.h>
#include <emscripten/heap.h>
#include <emscripten/val.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <new>
#include <utility>
#include <string>
#include <unistd.h>

#include "mrvol/error.h"
#include "mrvol/hierarchy_transfer.h"
#include "mrvol/limit_volume.h"
#include "mrvol/multires_mesh.h"
#include "mrvol/surface_buffers.h"
#include "mrvol/volume_editor.h"
#include "edit_options.h"
#include "guard.h"
#include "mesh_info.h"
#include "typed_arrays.h"

using emscripten::val;
using namespace mrvol;
using namespace mrvol::bindings;

namespace {

ErrorSlot errors("the input");

template <class F>
auto guarded(F&& f) -> decltype(f()) { return errors.guarded(std::forward<F>(f)); }

val takeError() { return errors.take(); }

TriangleMesh toMesh(const val& positions, const val& faces) {
  TriangleMesh m;
  m.positions = toVector<double>(positions, "positions");
  m.faces = toVector<uint32_t>(faces, "faces");
  return m;
}

val meshToJs(const TriangleMesh& m) {
  val out = val::object();
  out.set("positions", toTyped(m.positions));
  out.set("faces", toTyped(m.faces));
  return out;
}

// { vertex: Uint32Array, face: Uint32Array } (the OBJ line of each), or undefined.
std::unique_ptr<SourceLines> toLines(val lines) {
  if (lines.isUndefined() || lines.isNull()) return nullptr;
  auto out = std::make_unique<SourceLines>();
  out->vertex = toVector<uint32_t>(lines["vertex"], "lines.vertex");
  out->face = toVector<uint32_t>(lines["face"], "lines.face");
  return out;
}

val topologyToJs(const MeshTopology& t) {
  val out = val::object();
  out.set("edges", double(t.edges));
  out.set("boundaryEdges", double(t.boundaryEdges));
  out.set("components", double(t.components));
  out.set("closed", t.closed);
  out.set("genus", double(t.genus));
  return out;
}

// The scheme options as JS gives them: { scheme: 'loop' | 'butterfly' | 'linear', alpha, beta }.
struct JsScheme {
  std::string scheme;
  double alpha = 0, beta = 0;
};

SchemeOptions toScheme(const JsScheme& s) {
  SchemeOptions o;
  o.kind = parseSchemeName(s.scheme);
  o.alpha = s.alpha;
  o.beta = s.beta;
  return o;
}

// OBJ bytes (a Uint8Array) go into the heap once, as they are: no JS string, no UTF-8 conversion.
std::string bytesToHeap(const val& bytes, const char* what) {
  if (!bytes.instanceof(val::global("Uint8Array"))) throw Error(std::string(what) + " must be a Uint8Array");
  const double length = bytes["length"].as<double>();
  if (length > 2e9)
    throw Error("the file is too large to open: " + std::to_string(size_t(length)) +
                " bytes (mrvol reads OBJ files of up to 2 GB in WebAssembly)");
  std::string text(size_t(length), '\0');
  val(emscripten::typed_memory_view(text.size(), reinterpret_cast<uint8_t*>(text.data()))).call<void>("set", bytes);
  return text;
}

val js_readObj(val bytes) {
  return guarded([&] {
    SourceLines lines;
    ObjExtras extras;
    TriangleMesh mesh = mrvol::readObj(bytesToHeap(bytes, "the OBJ file"), &lines, &extras);
    const size_t welded = weldObjVertices(mesh, &lines, &extras);
    val out = meshToJs(mesh);
    out.set("welded", double(welded));
    mesh = TriangleMesh();
    val l = val::object();
    l.set("vertex", toTyped(lines.vertex));
    l.set("face", toTyped(lines.face));
    out.set("lines", l);
    out.set("polygons", double(extras.polygons));
    out.set("polygonTriangles", double(extras.polygonTriangles));
    if (!extras.texCoords.empty()) out.set("texCoords", toTyped(extras.texCoords));
    if (!extras.normals.empty()) out.set("normals", toTyped(extras.normals));
    if (!extras.colors.empty()) out.set("colors", toTyped(extras.colors));
    if (!extras.cornerTexCoords.empty()) out.set("cornerTexCoords", toTyped(extras.cornerTexCoords));
    if (!extras.cornerNormals.empty()) out.set("cornerNormals", toTyped(extras.cornerNormals));
    if (!extras.dropped.empty()) out.set("dropped", extras.dropped);
    return out;
  });
}
// The original OBJ bytes with the v lines' coordinates replaced: a Uint8Array.
val js_writeObjLike(val original, val positions) {
  return guarded([&] {
    const std::vector<double> x = toVector<double>(positions, "positions");
    if (x.size() % 3 != 0) throw Error("positions must hold 3 numbers per vertex");
    const std::string out = mrvol::writeObjLike(bytesToHeap(original, "the original OBJ file"), x.data(), x.size() / 3);
    return val(emscripten::typed_memory_view(out.size(), reinterpret_cast<const uint8_t*>(out.data()))).call<val>("slice");
  });
}
// OBJ text as a Uint8Array (lib/api.mjs decodes it): val(std::string) scanned the text byte by byte
// in JS, 2-3 times the core's writing, more on the threaded module's shared memory.
val js_writeObj(val positions, val faces) {
  return guarded([&] {
    const std::string out = mrvol::writeObj(toMesh(positions, faces));
    return val(emscripten::typed_memory_view(out.size(), reinterpret_cast<const uint8_t*>(out.data()))).call<val>("slice");
  });
}
val js_validate(val positions, val faces, val lines) {
  return guarded([&] { return topologyToJs(validateMesh(toMesh(positions, faces), toLines(lines).get())); });
}
val js_volume(val positions, val faces, val lines) {
  return guarded([&] {
    TriangleMesh m = toMesh(positions, faces);
    validateMesh(m, toLines(lines).get());
    return val(meshVolume(m));
  });
}

MultiresMesh* js_openMesh(val positions, val faces, int maxLevels, val lines) {
  return guarded([&] {
    // The OBJ lines only name what a refused mesh has wrong: copied into the heap for that only.
    try {
      return new MultiresMesh(toMesh(positions, faces), maxLevels);
    } catch (const Error&) {
      if (lines.isUndefined() || lines.isNull()) throw;
    }
    return new MultiresMesh(toMesh(positions, faces), maxLevels, toLines(lines).get());
  });
}
// A detected hierarchy handed to another instance of the module (hierarchy_transfer.h).
val js_hierarchyArrays(const MultiresMesh& m) {
  return guarded([&] {
    HierarchyArrays a = hierarchyArrays(m);
    val out = val::object();
    out.set("levels", a.levels);
    out.set("vertexCount", toTyped(a.vertexCount));
    out.set("coarseFaces", toTyped(a.coarseFaces));
    out.set("ends", toTyped(a.ends));
    out.set("wings", toTyped(a.wings));
    out.set("boundary", toTyped(a.boundary));
    out.set("inputIndex", toTyped(a.inputIndex));
    out.set("topology", topologyToJs(a.topology));
    return out;
  });
}
MultiresMesh* js_openWithHierarchy(val faces, val arrays) {
  return guarded([&] {
    HierarchyArrays a;
    a.levels = arrays["levels"].as<int>();
    a.vertexCount = toVector<uint32_t>(arrays["vertexCount"], "vertexCount");
    a.coarseFaces = toVector<uint32_t>(arrays["coarseFaces"], "coarseFaces");
    a.ends = toVector<uint32_t>(arrays["ends"], "ends");
    a.wings = toVector<uint32_t>(arrays["wings"], "wings");
    a.boundary = toVector<uint8_t>(arrays["boundary"], "boundary");
    a.inputIndex = toVector<uint32_t>(arrays["inputIndex"], "inputIndex");
    const val t = arrays["topology"];
    a.topology.edges = size_t(t["edges"].as<double>());
    a.topology.boundaryEdges = size_t(t["boundaryEdges"].as<double>());
    a.topology.components = size_t(t["components"].as<double>());
    a.topology.closed = t["closed"].as<bool>();
    a.topology.genus = long(t["genus"].as<double>());
    return new MultiresMesh(multiresFromArrays(toVector<uint32_t>(faces, "faces"), std::move(a)));
  });
}
// A mesh and its editor made in one instance of the module and taken over by a fresh one with a
// copy of the whole memory (the web app's file worker makes them, the page adopts them; see
// lib/api.mjs transferable): their addresses there, the objects at those addresses here, and room
// for the copy.
double js_meshAddress(const MultiresMesh& m) { return double(reinterpret_cast<uintptr_t>(&m)); }
double js_editorAddress(const VolumeEditor& e) { return double(reinterpret_cast<uintptr_t>(&e)); }
// Where the editor's cage coefficients (3 * cageSize doubles, the first of its coefficients) live:
// a drag reads them in place every step (no call, no copy out).
double js_editorCageAddress(const VolumeEditor& e) { return double(reinterpret_cast<uintptr_t>(e.coefficientData())); }
MultiresMesh* js_adoptMesh(double address) { return reinterpret_cast<MultiresMesh*>(uintptr_t(address)); }
VolumeEditor* js_adoptEditor(double address) { return reinterpret_cast<VolumeEditor*>(uintptr_t(address)); }
// Grows the memory (and emscripten's views of it) to at least `bytes`.
bool js_reserveMemory(double bytes) { return emscripten_resize_heap(size_t(bytes)); }
// The part of the memory in use: static data, stack and heap up to its top (sbrk); the rest was never
// handed out, so a transfer copies only this much.
double js_memoryInUse() { return double(reinterpret_cast<uintptr_t>(sbrk(0))); }
MultiresMesh* js_subdivideBase(val positions, val faces, int levels) {
  return guarded([&] { return new MultiresMesh(MultiresMesh::subdivide(toMesh(positions, faces), levels)); });
}
val js_subdivisionPositions(const MultiresMesh& m, val basePositions, JsScheme scheme) {
  return guarded(
      [&] { return toTyped(m.subdivisionPositions(toVector<double>(basePositions, "base positions"), toScheme(scheme))); });
}

val js_info(const MultiresMesh& m, val positions) {
  return guarded([&] { return meshInfoToJs(m.info(toVector<double>(positions, "positions"))); });
}
val js_faces(const MultiresMesh& m) { return guarded([&] { return toTyped(m.faces()); }); }
val js_levelFaces(const MultiresMesh& m, int level) { return guarded([&] { return toTyped(m.levelFaces(level)); }); }
val js_depths(const MultiresMesh& m) { return guarded([&] { return depthsToJs(m.hierarchy()); }); }
bool js_checkPositions(const MultiresMesh& m, val p) {
  return guarded([&] { return m.checkPositions(toVector<double>(p, "positions")), true; });
}
val js_analyze(const MultiresMesh& m, val p, int level, JsScheme scheme) {
  return guarded([&] { return toTyped(m.analyze(toVector<double>(p, "positions"), level, toScheme(scheme))); });
}
val js_synthesize(const MultiresMesh& m, val c, int level, JsScheme scheme) {
  return guarded(
      [&] { return toTyped(m.synthesize(toVector<double>(c, "coefficients"), level, toScheme(scheme))); });
}
val js_liftingSteps(const MultiresMesh& m, int level, JsScheme scheme) {
  return guarded([&] {
    val out = val::array();
    for (const LiftingStep& step : m.liftingSteps(level, toScheme(scheme))) {
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
val js_liftingStepCount(const MultiresMesh& m, int level, JsScheme scheme) {
  return guarded([&] { return val(m.liftingStepCount(level, toScheme(scheme))); });
}
val js_synthesizeSteps(const MultiresMesh& m, val c, int level, int steps, JsScheme scheme) {
  return guarded([&] {
    return toTyped(m.synthesizeSteps(toVector<double>(c, "coefficients"), level, steps, toScheme(scheme)));
  });
}
val js_analyzeSteps(const MultiresMesh& m, val c, int level, int steps, JsScheme scheme) {
  return guarded([&] {
    return toTyped(m.analyzeSteps(toVector<double>(c, "coefficients"), level, steps, toScheme(scheme)));
  });
}
val js_transposeSteps(const MultiresMesh& m, val c, int level, int steps, JsScheme scheme) {
  return guarded([&] {
    return toTyped(m.transposeSteps(toVector<double>(c, "covector"), level, steps, toScheme(scheme)));
  });
}
val js_hierarchyOrder(const MultiresMesh& m) { return guarded([&] { return toTyped(m.hierarchy().inputIndex); }); }
val js_roundtripError(const MultiresMesh& m, val positions, int level, JsScheme scheme) {
  return guarded([&] { return val(m.roundtripError(toVector<double>(positions, "positions"), level, toScheme(scheme))); });
}

TensorStorage toStorage(const std::string& name) {
  if (name == "cage") return TensorStorage::Cage;
  if (name == "full") return TensorStorage::Full;
  throw Error("unknown tensor storage '" + name + "' (expected cage or full)");
}

Theta* js_computeTheta(const MultiresMesh& m, int level, JsScheme scheme,
                       std::string storage, val onProgress) {
  return guarded([&]() -> Theta* {
    SchemeOptions o = toScheme(scheme);
    TensorProgress progress;
    struct Ctx { val* fn; } ctx{&onProgress};
    if (onProgress.typeOf().as<std::string>() == "function") {
      progress.user = &ctx;
      progress.callback = [](double fraction, void* user) {
        val r = (*static_cast<Ctx*>(user)->fn)(fraction);
        return !(r.isFalse());
      };
    }
    auto theta = std::make_unique<Theta>();
    theta->tensor = m.computeTensor(level, o, toStorage(storage), progress);
    theta->header = m.thetaHeader(theta->tensor, o);
    return theta.release();
  });
}
val js_thetaVolume(const MultiresMesh& m, const Theta& t, int level, JsScheme scheme, val positions) {
  return guarded([&] {
    SchemeOptions o = toScheme(scheme);
    m.checkTheta(t.header, level, o);
    return val(m.tensorVolume(t.tensor, o, toVector<double>(positions, "positions")));
  });
}
// The Loop limit surface (limit_volume.h): its volume, and theta^e of it.
val js_limitVolume(val positions, val faces, val lines) {
  return guarded([&] {
    TriangleMesh m = toMesh(positions, faces);
    validateMesh(m, toLines(lines).get());
    return val(limitVolume(m));
  });
}
val js_meshLimitVolume(const MultiresMesh& m, val positions) {
  return guarded([&] { return val(m.limitVolume(toVector<double>(positions, "positions"))); });
}
Theta* js_computeLimitTheta(const MultiresMesh& m, int level, JsScheme scheme, std::string storage) {
  return guarded([&]() -> Theta* {
    SchemeOptions o = toScheme(scheme);
    auto theta = std::make_unique<Theta>();
    theta->tensor = m.computeLimitTensor(level, o, toStorage(storage));
    theta->header = m.thetaHeader(theta->tensor, o);
    theta->header.limitSurface = true;
    return theta.release();
  });
}
val js_limitThetaVolume(const MultiresMesh& m, const Theta& t, int level, JsScheme scheme, val positions) {
  return guarded([&] {
    SchemeOptions o = toScheme(scheme);
    m.checkTheta(t.header, level, o, true);
    return val(m.limitTensorVolume(t.tensor, o, toVector<double>(positions, "positions")));
  });
}

val js_estimateTheta(const MultiresMesh& m, int level, JsScheme scheme) {
  return guarded([&] {
    TensorEstimate e = m.estimateTensor(level, toScheme(scheme));
    val out = val::object();
    out.set("cageSize", double(e.cageSize));
    out.set("maxPatch", double(e.maxPatch));
    out.set("entries", double(e.entries));
    out.set("bytes", double(e.bytes));
    out.set("denseBytes", double(e.denseBytes));
    out.set("milliseconds", e.milliseconds);
    out.set("fits", e.fits());
    return out;
  });
}
val js_fingerprint(const MultiresMesh& m) {
  return guarded([&] {
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(m.fingerprint()));
    return val(std::string(hex));
  });
}
Theta* js_readTheta(val bytes) {
  return guarded([&]() -> Theta* {
    std::vector<uint8_t> v = toVector<uint8_t>(bytes, "theta bytes");
    auto theta = std::make_unique<Theta>();
    theta->tensor = readThetaFile(std::string(v.begin(), v.end()), &theta->header);
    return theta.release();
  });
}
val js_thetaBytes(const Theta& t) {
  return guarded([&] {
    std::string bytes = writeThetaFile(t.tensor, t.header);
    return val(emscripten::typed_memory_view(bytes.size(), reinterpret_cast<const uint8_t*>(bytes.data())))
        .call<val>("slice");
  });
}
val js_thetaEntries(const Theta& t) {
  return guarded([&] {
    VolumeTensor::Entries e = t.tensor.entries();
    val out = val::object();
    out.set("i", toTyped(e.i));
    out.set("j", toTyped(e.j));
    out.set("k", toTyped(e.k));
    out.set("values", toTyped(e.values));
    return out;
  });
}
val js_thetaInfo(const Theta& t) {
  return guarded([&] {
    val out = val::object();
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(t.header.fingerprint));
    out.set("formatVersion", double(t.header.formatVersion));
    out.set("scheme", std::string(schemeName(t.header.scheme.kind)));
    out.set("alpha", t.header.scheme.alpha);
    out.set("beta", t.header.scheme.beta);
    out.set("levels", t.header.levels);
    out.set("level", t.tensor.level);
    out.set("storage", std::string(t.tensor.storage == TensorStorage::Full ? "full" : "cage"));
    out.set("surface", std::string(t.header.limitSurface ? "limit" : "mesh"));
    out.set("fingerprint", std::string(hex));
    out.set("vertices", double(t.tensor.vertexCount));
    out.set("nnzFull", t.tensor.nnzFull ? val(double(t.tensor.nnzFull)) : val::null());
    out.set("nnzStored", double(t.tensor.storedCount()));
    out.set("bytes", double(t.tensor.bytes()));
    return out;
  });
}

VolumeEditor* js_createEditor(const MultiresMesh& m, int level, JsScheme scheme, val positions) {
  return guarded([&]() -> VolumeEditor* {
    const std::vector<double> p = toVector<double>(positions, "positions");
    m.checkPositions(p);
    return new VolumeEditor(m.hierarchy(), m.transform(toScheme(scheme)), level, p.data());
  });
}
bool js_editorUseTheta(VolumeEditor& e, const MultiresMesh& m, const Theta& t, JsScheme scheme) {
  return guarded([&] {
    m.checkTheta(t.header, e.level(), toScheme(scheme), e.limitSurface());
    e.useTensor(t.tensor);
    return true;
  });
}
// The cage polynomial built from the fine triangles; false (matrix-free) when the builder refuses.
bool js_editorUsePolynomial(VolumeEditor& e) { return guarded([&] { return e.usePolynomial(); }); }
bool js_editorUseMatrixFree(VolumeEditor& e) { return guarded([&] { return e.useMatrixFree(), true; }); }
val js_editorPath(const VolumeEditor& e) { return guarded([&] { return val(std::string(gradientPathName(e.path()))); }); }
val js_editorCageVertices(const VolumeEditor& e) { return guarded([&] { return toTyped(e.cageVertices()); }); }
val js_editorCageIndexOf(const VolumeEditor& e, double v) {
  return guarded([&] {
    if (!(v >= 0) || v != std::floor(v) || v > 4294967295.0) throw Error("vertex index must be a non-negative integer");
    return val(double(e.cageIndexOf(uint32_t(v))));
  });
}
// The cage is the first 3 * cageSize coefficients: copied out once (a drag asks for it every step).
val js_editorCagePositions(const VolumeEditor& e) {
  return guarded([&] { return val(emscripten::typed_memory_view(3 * size_t(e.cageSize()), e.coefficientData())).call<val>("slice"); });
}
val js_editorPositions(const VolumeEditor& e) { return guarded([&] { return toTyped(e.positions()); }); }
val js_editorCoefficients(const VolumeEditor& e) { return guarded([&] { return toTyped(e.coefficients()); }); }
val js_editorVolume(const VolumeEditor& e) { return guarded([&] { return val(e.volume()); }); }
val js_editorReference(const VolumeEditor& e) { return guarded([&] { return val(e.referenceVolume()); }); }
bool js_editorSetReference(VolumeEditor& e, double v) { return guarded([&] { return e.setReferenceVolume(v), true; }); }
bool js_editorSetFreeSet(VolumeEditor& e, std::string mode, val list, val detailLevels) {
  return guarded([&] {
    std::vector<int> levels = detailLevels.isUndefined() ? std::vector<int>{} : toVector<int>(detailLevels, "detail levels");
    const FreeCage cage = freeCageMode(mode);
    e.setFreeSet(cage, cage == FreeCage::List ? toVector<uint32_t>(list, "free set") : std::vector<uint32_t>{}, levels);
    return true;
  });
}
bool js_editorSetParts(VolumeEditor& e, val parts, val references) {
  return guarded([&] {
    std::vector<std::vector<uint32_t>> p;
    const unsigned n = parts["length"].as<unsigned>();
    for (unsigned i = 0; i < n; ++i) p.push_back(toVector<uint32_t>(parts[i], "part"));
    std::vector<double> refs = references.isUndefined() || references.isNull() ? std::vector<double>{}
                                                                                : toVector<double>(references, "references");
    e.setParts(p, refs);
    return true;
  });
}
// The limit surface's volume kept instead of the mesh's (the form of this mesh, kept by it).
bool js_editorUseLimitSurface(VolumeEditor& e, const MultiresMesh& m) {
  return guarded([&] { return e.useLimitSurface(m.limitForm()), true; });
}
bool js_editorKeepCentroid(VolumeEditor& e, bool keep) { return guarded([&] { return e.keepCentroid(keep), true; }); }
val vec3ToJs(Vec3 v) { return toTyped(std::vector<double>{v.x, v.y, v.z}); }
val js_editorCentroid(const VolumeEditor& e) { return guarded([&] { return vec3ToJs(e.centroid()); }); }
val js_editorReferenceCentroid(const VolumeEditor& e) { return guarded([&] { return vec3ToJs(e.referenceCentroid()); }); }
val js_editorPartVolumes(const VolumeEditor& e) { return guarded([&] { return toTyped(e.partVolumes()); }); }

val js_editorDeformCage(VolumeEditor& e, val target, val held, val options) {
  return guarded([&] {
    return reportToJs(e.deformCage(toVector<double>(target, "cage target"), toVector<uint8_t>(held, "held flags"),
                                   toEditOptions(options)));
  });
}
val js_editorCorrect(VolumeEditor& e, val held, val options) {
  return guarded([&] { return reportToJs(e.correct(toVector<uint8_t>(held, "held flags"), toEditOptions(options))); });
}
val js_editorGradient(const VolumeEditor& e, std::string path) {
  return guarded([&] {
    std::vector<double> g;
    if (path == "tensor" || path == "polynomial") e.gradientTensor(g);
    else if (path == "matrix-free") e.gradientMatrixFree(g);
    else throw Error("unknown gradient path '" + path + "' (tensor, polynomial or matrix-free)");
    return toTyped(g);
  });
}

// Renderer buffers: views into WASM memory (no copy), valid until the memory grows.
SurfaceBuffers* js_createSurfaceBuffers(const MultiresMesh& m) {
  return guarded([&] { return new SurfaceBuffers(m.hierarchy()); });
}
val js_surfaceUpdate(SurfaceBuffers& s, const VolumeEditor& e, bool normals) {
  return guarded([&] {
    s.update(e, normals);
    return val(double(s.version()));
  });
}
// { positions: [first, end), normals: [first, end) }: the caller's vertices the last writes rewrote.
val js_surfaceRanges(const SurfaceBuffers& s) {
  return guarded([&] {
    val out = val::object();
    out.set("positions", val::array(std::vector<double>{double(s.positionsFirst()), double(s.positionsEnd())}));
    out.set("normals", val::array(std::vector<double>{double(s.normalsFirst()), double(s.normalsEnd())}));
    return out;
  });
}
// Views of the buffers: no allocation in WASM, nothing that throws (unguarded, as the getters below).
val js_surfacePositions(const SurfaceBuffers& s) { return val(emscripten::typed_memory_view(3 * s.vertexCount(), s.positions())); }
val js_surfaceNormals(const SurfaceBuffers& s) { return val(emscripten::typed_memory_view(3 * s.vertexCount(), s.normals())); }

}  // namespace

// Every registration below runs guarded except the ones that only read a field or an address
// (levels, level, cageSize, limitSurface, keepsCentroid, the addresses, _reserveMemory's C call,
// _takeError): they neither allocate nor throw. An exception out of a call would reach JS
// opaque and, in the threaded module, keep the exception dispatch lock (landing_pad_context.cpp).
EMSCRIPTEN_BINDINGS(mrvol) {
  using namespace emscripten;
  value_object<JsScheme>("_Scheme")
      .field("scheme", &JsScheme::scheme)
      .field("alpha", &JsScheme::alpha)
      .field("beta", &JsScheme::beta);
  function("_takeError", &takeError);
  function("_readObj", &js_readObj);
  function("_writeObj", &js_writeObj);
  function("_writeObjLike", &js_writeObjLike);
  function("_validate", &js_validate);
  function("_volume", &js_volume);
  function("_limitVolume", &js_limitVolume);
  function("_openMesh", &js_openMesh, allow_raw_pointers());
  function("_subdivideBase", &js_subdivideBase, allow_raw_pointers());
  function("_openWithHierarchy", &js_openWithHierarchy, allow_raw_pointers());
  function("_meshAddress", &js_meshAddress);
  function("_editorAddress", &js_editorAddress);
  function("_adoptMesh", &js_adoptMesh, allow_raw_pointers());
  function("_adoptEditor", &js_adoptEditor, allow_raw_pointers());
  function("_reserveMemory", &js_reserveMemory);
  function("_memoryInUse", &js_memoryInUse);
  class_<MultiresMesh>("_MultiresMesh")
      .function("levels", &MultiresMesh::levels)
      .function("info", &js_info)
      .function("faces", &js_faces)
      .function("depths", &js_depths)
      .function("levelFaces", &js_levelFaces)
      .function("checkPositions", &js_checkPositions)
      .function("subdivisionPositions", &js_subdivisionPositions)
      .function("analyze", &js_analyze)
      .function("synthesize", &js_synthesize)
      .function("roundtripError", &js_roundtripError)
      .function("liftingSteps", &js_liftingSteps)
      .function("liftingStepCount", &js_liftingStepCount)
      .function("synthesizeSteps", &js_synthesizeSteps)
      .function("analyzeSteps", &js_analyzeSteps)
      .function("transposeSteps", &js_transposeSteps)
      .function("hierarchyOrder", &js_hierarchyOrder)
      .function("computeTheta", &js_computeTheta, allow_raw_pointers())
      .function("thetaVolume", &js_thetaVolume)
      .function("limitVolume", &js_meshLimitVolume)
      .function("computeLimitTheta", &js_computeLimitTheta, allow_raw_pointers())
      .function("limitThetaVolume", &js_limitThetaVolume)
      .function("fingerprint", &js_fingerprint)
      .function("hierarchyArrays", &js_hierarchyArrays)
      .function("estimateTheta", &js_estimateTheta)
      .function("createEditor", &js_createEditor, allow_raw_pointers());
  class_<VolumeEditor>("_VolumeEditor")
      // CageEditor members as this class's: embind takes member pointers of the bound class only
      .function("level", static_cast<int (VolumeEditor::*)() const>(&VolumeEditor::level))
      .function("cageSize", static_cast<uint32_t (VolumeEditor::*)() const>(&VolumeEditor::cageSize))
      .function("useTheta", &js_editorUseTheta)
      .function("usePolynomial", &js_editorUsePolynomial)
      .function("useMatrixFree", &js_editorUseMatrixFree)
      .function("path", &js_editorPath)
      .function("cageVertices", &js_editorCageVertices)
      .function("cageIndexOf", &js_editorCageIndexOf)
      .function("cagePositions", &js_editorCagePositions)
      .function("cageAddress", &js_editorCageAddress)
      .function("positions", &js_editorPositions)
      .function("coefficients", &js_editorCoefficients)
      .function("volume", &js_editorVolume)
      .function("referenceVolume", &js_editorReference)
      .function("setReferenceVolume", &js_editorSetReference)
      .function("setFreeSet", &js_editorSetFreeSet)
      .function("setParts", &js_editorSetParts)
      .function("partVolumes", &js_editorPartVolumes)
      .function("useLimitSurface", &js_editorUseLimitSurface)
      .function("limitSurface", &VolumeEditor::limitSurface)
      .function("keepCentroid", &js_editorKeepCentroid)
      .function("keepsCentroid", static_cast<bool (VolumeEditor::*)() const>(&VolumeEditor::keepsCentroid))
      .function("centroid", &js_editorCentroid)
      .function("referenceCentroid", &js_editorReferenceCentroid)
      .function("deformCage", &js_editorDeformCage)
      .function("correct", &js_editorCorrect)
      .function("gradient", &js_editorGradient);
  class_<Theta>("_Theta")
      .function("info", &js_thetaInfo)
      .function("bytes", &js_thetaBytes)
      .function("entries", &js_thetaEntries);
  function("_readTheta", &js_readTheta, allow_raw_pointers());
  function("_createSurfaceBuffers", &js_createSurfaceBuffers, allow_raw_pointers());
  class_<SurfaceBuffers>("_SurfaceBuffers")
      .function("update", &js_surfaceUpdate)
      .function("positions", &js_surfacePositions)
      .function("normals", &js_surfaceNormals)
      .function("ranges", &js_surfaceRanges);
}
