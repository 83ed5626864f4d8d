#include "mrvol/vertex_order.h"

#include "mrvol/corners.h"

namespace mrvol {

std::vector<uint32_t> renumberByFirstAppearance(std::vector<uint32_t>& faces, size_t vertexCount) {
  for (uint32_t v : faces)
    if (v >= vertexCount) return {};
  std::vector<uint32_t> callerToLocal(vertexCount, kNone);
  std::vector<uint32_t> localToCaller(vertexCount);
  uint32_t next = 0;
  for (uint32_t& v : faces) {
    uint32_t& local = callerToLocal[v];
    if (local == kNone) localToCaller[next] = v, local = next++;
    v = local;
  }
  for (uint32_t v = 0; v < vertexCount; ++v)
    if (callerToLocal[v] == kNone) localToCaller[next++] = v;
  return localToCaller;
}

void restoreNumbering(std::vector<uint32_t>& faces, const std::vector<uint32_t>& localToCaller) {
  for (uint32_t& v : faces) v = localToCaller[v];
}

}  // namespace mrvol
