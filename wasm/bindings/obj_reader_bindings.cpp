// embind layer for OBJ files read in chunks (mrvol/obj_reader.h): the caller writes each chunk
// straight into a buffer in the heap (no JS string, no whole-file copy), then feeds it. Errors stay
// here (guard.h) until lib/api.mjs takes them with _takeObjReaderError() and throws MrvolError.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mrvol/obj_reader.h"
#include "guard.h"
#include "typed_arrays.h"

using emscripten::val;
using namespace mrvol;
using namespace mrvol::bindings;

namespace {

ErrorSlot readerErrors("the OBJ file");

val takeReaderError() { return readerErrors.take(); }

// Each array goes to JS and is freed at once, so that the heap holds one copy at a time.
template <class T>
val moveToTyped(std::vector<T>& v) {
  val out = toTyped(v);
  std::vector<T>().swap(v);
  return out;
}

class JsObjReader {
 public:
  explicit JsObjReader(double expectedBytes) : reader_(size_t(expectedBytes > 0 ? expectedBytes : 0)) {}

  // The heap address of room for `bytes` bytes: the next chunk goes there (HEAPU8.set), then feed.
  double buffer(double bytes) {
    return readerErrors.guarded([&] {
      chunk_.resize(size_t(bytes));
      return double(reinterpret_cast<uintptr_t>(chunk_.data()));
    });
  }
  // Reads the first `bytes` bytes of the buffer; false (and an error to take) on a bad line.
  bool feed(double bytes) {
    return readerErrors.guarded([&] {
      if (size_t(bytes) > chunk_.size()) throw Error("the OBJ chunk is larger than its buffer");
      reader_.feed(std::string_view(chunk_.data(), size_t(bytes)));
      return true;
    });
  }
  // The mesh, as _readObj gives it.
  val finish() {
    return readerErrors.guarded([&] {
      std::vector<char>().swap(chunk_);
      SourceLines lines;
      ObjExtras extras;
      TriangleMesh mesh = reader_.finish(&lines, &extras);
      const size_t welded = weldObjVertices(mesh, &lines, &extras);
      val out = val::object();
      out.set("welded", double(welded));
      out.set("positions", moveToTyped(mesh.positions));
      out.set("faces", moveToTyped(mesh.faces));
      val l = val::object();
      l.set("vertex", moveToTyped(lines.vertex));
      l.set("face", moveToTyped(lines.face));
      out.set("lines", l);
      out.set("polygons", double(extras.polygons));
      out.set("polygonTriangles", double(extras.polygonTriangles));
      if (!extras.texCoords.empty()) out.set("texCoords", moveToTyped(extras.texCoords));
      if (!extras.normals.empty()) out.set("normals", moveToTyped(extras.normals));
      if (!extras.colors.empty()) out.set("colors", moveToTyped(extras.colors));
      if (!extras.cornerTexCoords.empty()) out.set("cornerTexCoords", moveToTyped(extras.cornerTexCoords));
      if (!extras.cornerNormals.empty()) out.set("cornerNormals", moveToTyped(extras.cornerNormals));
      if (!extras.dropped.empty()) out.set("dropped", extras.dropped);
      return out;
    });
  }
  double bytesRead() const { return double(reader_.bytesRead()); }

 private:
  ObjReader reader_;
  std::vector<char> chunk_;
};

// Made by a guarded function, not an embind constructor: the reader allocates its parser, and a
// constructor's exception would leave WASM (null and an error to take instead).
JsObjReader* createReader(double expectedBytes) {
  return readerErrors.guarded([&] { return new JsObjReader(expectedBytes); });
}

}  // namespace

EMSCRIPTEN_BINDINGS(mrvol_obj_reader) {
  using namespace emscripten;
  function("_takeObjReaderError", &takeReaderError);
  function("_createObjReader", &createReader, allow_raw_pointers());
  class_<JsObjReader>("_ObjReader")
      .function("buffer", &JsObjReader::buffer)
      .function("feed", &JsObjReader::feed)
      .function("finish", &JsObjReader::finish)
      .function("bytesRead", &JsObjReader::bytesRead);  // reads a count: unguarded, it cannot throw
}
