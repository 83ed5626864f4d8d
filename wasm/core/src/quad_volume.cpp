#include "mrvol/quad_volume.h"

namespace mrvol {

FineForm bilinearPatchForm(const std::vector<uint32_t>& quads) {
  FineForm form;
  form.corners.reserve(quads.size() * 3);
  form.weights.reserve(quads.size());
  for (size_t q = 0; q + 3 < quads.size(); q += 4) {
    const uint32_t a = quads[q], b = quads[q + 1], c = quads[q + 2], d = quads[q + 3];
    form.corners.insert(form.corners.end(), {a, b, c, a, c, d, a, b, d, b, c, d});
    form.weights.insert(form.weights.end(), 4, 1.0 / 12.0);
  }
  return form;
}

Vec3 quadReferencePoint(const QuadMesh& mesh) {
  TriangleMesh t;
  t.positions = mesh.positions;
  t.faces = triangulateQuads(mesh.quads);
  return volumeReferencePoint(t);
}

double bilinearVolume(const QuadMesh& mesh) {
  return bilinearPatchForm(mesh.quads).evaluate(mesh.positions.data(), quadReferencePoint(mesh));
}

}  // namespace mrvol
