// embind layer for mesh files other than OBJ (mrvol/io_formats.h): bytes in (a Uint8Array copied
// once into the heap), typed arrays out. Like bindings.cpp, a core error never crosses as an
// exception: it is kept here and lib/api.mjs takes it with _takeIoError() and throws MrvolError.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mrvol/error.h"
#include "mrvol/io_formats.h"
#include "guard.h"
#include "typed_arrays.h"

using emscripten::val;
using namespace mrvol;
using namespace mrvol::bindings;

namespace {

ErrorSlot ioErrors("the file");

template <class F>
val guardedIo(F&& f) { return ioErrors.guarded(std::forward<F>(f)); }

val takeIoError() { return ioErrors.take(); }

// File bytes in the heap, left uninitialised until the one copy from JS fills them (a std::string
// would first zero them: a pass over the whole file for nothing).
struct HeapBytes {
  std::unique_ptr<char[]> data;
  size_t size = 0;
  operator std::string_view() const { return {data.get(), size}; }
};

// One copy from the JS Uint8Array into the heap: TypedArray.prototype.set onto a view of it.
HeapBytes bytesOf(const val& array, const char* what) {
  if (array.isUndefined() || array.isNull()) throw Error(std::string(what) + " is missing");
  HeapBytes out;
  out.size = array["length"].as<size_t>();
  out.data.reset(new char[out.size]);
  val(emscripten::typed_memory_view(out.size, reinterpret_cast<uint8_t*>(out.data.get()))).call<void>("set", array);
  return out;
}

// [[uri, Uint8Array], ...] (or undefined): the bytes copied into `storage`, viewed by the result.
GltfResources resourcesOf(const val& resources, std::vector<HeapBytes>& storage) {
  GltfResources out;
  if (resources.isUndefined() || resources.isNull()) return out;
  const size_t n = resources["length"].as<size_t>();
  storage.reserve(n);
  for (size_t i = 0; i < n; ++i) storage.push_back(bytesOf(resources[i][1], "resource bytes"));
  for (size_t i = 0; i < n; ++i) out.emplace_back(resources[i][0].as<std::string>(), storage[i]);
  return out;
}

// bytes: Uint8Array; name: file name or ""; format: "" (detect) or a format name; resources:
// [[uri, Uint8Array], ...] for a .gltf's sidecar files.
val js_readMesh(val bytes, std::string name, std::string format, val resources) {
  return guardedIo([&] {
    const HeapBytes data = bytesOf(bytes, "file bytes");
    std::vector<HeapBytes> storage;
    const GltfResources extra = resourcesOf(resources, storage);
    ImportedMesh m = format.empty() ? readMeshFile(data, name, extra) : readMeshFile(data, parseFormatName(format), extra);
    val out = val::object();
    out.set("positions", toTyped(m.mesh.positions));
    out.set("faces", toTyped(m.mesh.faces));
    out.set("format", std::string(formatName(m.format)));
    out.set("variant", m.variant);
    out.set("sourceVertex", toTyped(m.sourceVertex));
    out.set("sourceVertices", double(m.sourceVertices));
    out.set("sourceFaces", double(m.sourceFaces));
    out.set("welded", double(m.welded));
    out.set("triangulated", double(m.triangulated));
    if (m.format == MeshFormat::Obj) {
      val lines = val::object();
      lines.set("vertex", toTyped(m.objLines.vertex));
      lines.set("face", toTyped(m.objLines.face));
      out.set("lines", lines);
    }
    return out;
  });
}

val js_detectFormat(val bytes, std::string name) {
  return guardedIo([&] { return val(std::string(formatName(detectFormat(bytesOf(bytes, "file bytes"), name)))); });
}

val js_writeGlb(val positions, val faces) {
  return guardedIo([&] {
    TriangleMesh m;
    m.positions = emscripten::convertJSArrayToNumberVector<double>(positions);
    m.faces = emscripten::convertJSArrayToNumberVector<uint32_t>(faces);
    const std::string glb = writeGlb(m);
    return val(emscripten::typed_memory_view(glb.size(), reinterpret_cast<const uint8_t*>(glb.data()))).call<val>("slice");
  });
}

// The GLB of a glTF / GLB source with the edited mesh's positions (same triangles as read).
val js_writeGlbKeeping(val source, std::string name, std::string format, val resources, val positions, val faces) {
  return guardedIo([&] {
    const HeapBytes data = bytesOf(source, "source bytes");
    std::vector<HeapBytes> storage;
    const GltfResources extra = resourcesOf(resources, storage);
    TriangleMesh m;
    m.positions = emscripten::convertJSArrayToNumberVector<double>(positions);
    m.faces = emscripten::convertJSArrayToNumberVector<uint32_t>(faces);
    const MeshFormat f = format.empty() ? detectFormat(data, name) : parseFormatName(format);
    const std::string glb = writeGlbKeeping(data, f, extra, m);
    return val(emscripten::typed_memory_view(glb.size(), reinterpret_cast<const uint8_t*>(glb.data()))).call<val>("slice");
  });
}

}  // namespace

EMSCRIPTEN_BINDINGS(mrvol_io) {
  using namespace emscripten;
  function("_writeGlbKeeping", &js_writeGlbKeeping);
  function("_takeIoError", &takeIoError);
  function("_readMesh", &js_readMesh);
  function("_detectFormat", &js_detectFormat);
  function("_writeGlb", &js_writeGlb);
}
