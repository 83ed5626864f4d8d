// libFuzzer target: arbitrary bytes through the STL reader (mrvol::readStl), then the checks of
// mesh_file_checks.h (well-formed result, welding complete, validation answers, GLB round trip);
// a binary STL is also read welded in blocks on 3 threads, which must give the same result or
// the same message.
//
//   build/fuzz/fuzz_stl build/fuzz/corpus-fuzz_stl
#include <cstdlib>
#include <cstring>
#include <string>

#include "mesh_file_checks.h"
#include "mrvol/thread_pool.h"

namespace {

// The result, or the message of the error, of one read.
struct Outcome {
  bool ok = false;
  mrvol::ImportedMesh mesh;
  std::string message;
};

Outcome readOnce(std::string_view bytes) {
  Outcome o;
  try {
    o.mesh = mrvol::readStl(bytes);
    o.ok = true;
  } catch (const mrvol::Error& e) {
    o.message = e.what();
  } catch (const std::bad_alloc&) {
    o.message = "bad_alloc";
  }
  return o;
}

bool same(const Outcome& a, const Outcome& b) {
  if (a.ok != b.ok || a.message != b.message) return false;
  if (!a.ok) return true;
  const mrvol::ImportedMesh &x = a.mesh, &y = b.mesh;
  return x.mesh.faces == y.mesh.faces && x.sourceVertex == y.sourceVertex && x.variant == y.variant &&
         x.sourceVertices == y.sourceVertices && x.sourceFaces == y.sourceFaces && x.welded == y.welded &&
         x.mesh.positions.size() == y.mesh.positions.size() &&
         std::memcmp(x.mesh.positions.data(), y.mesh.positions.data(), 8 * x.mesh.positions.size()) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const unsigned threads = mrvol::setThreadCount(3);
  (void)threads;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  // Grain 0: one block below 32,768 triangles (the one-pass weld); grain 1: up to 3 blocks.
  mrvol::setGrainCap(0);
  const Outcome one = readOnce(bytes);
  mrvol::setGrainCap(1);
  const Outcome blocks = readOnce(bytes);
  mrvol::setGrainCap(0);
  if (!same(one, blocks)) std::abort();
  return fuzzing::runReader(data, size, [](std::string_view b) { return mrvol::readStl(b); });
}
