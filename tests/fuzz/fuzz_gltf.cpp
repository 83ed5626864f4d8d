// libFuzzer target: arbitrary bytes through the glTF readers: as GLB when they start with the
// magic "glTF", else as .gltf JSON; one sidecar buffer "a.bin" (the input's last quarter) is
// offered for URIs. Then the checks of mesh_file_checks.h.
//
//   build/fuzz/fuzz_gltf build/fuzz/corpus-fuzz_gltf -dict=tests/fuzz/gltf.dict
#include "mesh_file_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return fuzzing::runReader(data, size, [](std::string_view bytes) {
    const mrvol::GltfResources sidecar = {{"a.bin", bytes.substr(bytes.size() - bytes.size() / 4)}};
    if (bytes.substr(0, 4) == "glTF") return mrvol::readGlb(bytes, sidecar);
    return mrvol::readGltf(bytes, sidecar);
  });
}
