#include "mrvol/quad_lifting.h"

#include <algorithm>
#include <string>

#include "mrvol/corners.h"
#include "mrvol/error.h"
#include "mrvol/step_builder.h"

namespace mrvol {

std::vector<LiftingStep> catmullClarkLevel(const QuadHierarchy& q, int l, bool* invertible) {
  if (l < 1 || l > q.levels()) throw Error("level " + std::to_string(l) + " is out of range 1.." + std::to_string(q.levels()));
  const std::vector<uint32_t>& coarse = q.quads[l - 1];
  const QuadSplit& split = q.splits[l - 1];
  const uint32_t V = q.h.vertexCount[l - 1];

  // Per old vertex: incident edges and quads.
  std::vector<std::vector<uint32_t>> edgesAt(V), facesAt(V);
  for (uint32_t i = 0; i < split.edges.size(); ++i) edgesAt[split.edges[i].a].push_back(i), edgesAt[split.edges[i].b].push_back(i);
  for (uint32_t f = 0; f < split.facePoint.size(); ++f)
    for (int k = 0; k < 4; ++k) facesAt[coarse[4 * f + k]].push_back(split.facePoint[f]);
  std::vector<uint8_t> onBoundary(V, 0);
  for (const auto& e : split.edges)
    if (e.face1 == kNone) onBoundary[e.a] = onBoundary[e.b] = 1;

  StepBuilder faces, edges;
  for (uint32_t f = 0; f < split.facePoint.size(); ++f)
    for (int k = 0; k < 4; ++k) faces.add(split.facePoint[f], coarse[4 * f + k], 0.25);
  for (const auto& e : split.edges) {
    if (e.face1 == kNone) {
      edges.add(e.point, e.a, 0.5), edges.add(e.point, e.b, 0.5);
    } else {
      edges.add(e.point, e.a, 0.25), edges.add(e.point, e.b, 0.25);
      edges.add(e.point, e.face0, 0.25), edges.add(e.point, e.face1, 0.25);
    }
  }

  // Layers: 0 for boundary vertices and interior ones of valence != 3; an interior valence-3
  // vertex is one more than the nearest layer among its neighbours (breadth first).
  std::vector<int> layer(V, -1);
  std::vector<uint32_t> queue;
  for (uint32_t v = 0; v < V; ++v)
    if (onBoundary[v] || edgesAt[v].size() != 3) layer[v] = 0, queue.push_back(v);
  for (size_t head = 0; head < queue.size(); ++head) {
    const uint32_t v = queue[head];
    for (uint32_t i : edgesAt[v]) {
      const uint32_t w = split.edges[i].a == v ? split.edges[i].b : split.edges[i].a;
      if (layer[w] < 0) layer[w] = layer[v] + 1, queue.push_back(w);
    }
  }
  int layers = 0;
  if (invertible) *invertible = true;
  for (uint32_t v = 0; v < V; ++v) {
    if (layer[v] < 0) {
      if (!invertible)
        throw Error("level " + std::to_string(l - 1) + " has a closed component whose vertices all have valence 3 (a cube, " +
                    "vertex " + std::to_string(q.h.inputIndex[v]) + "): Catmull-Clark subdivision maps its alternating " +
                    "pattern to zero, so no perfect-reconstruction filter bank reproduces it there");
      // Synthesis only: the plain vertex rule, whose factor (n - 3) / n is 0 here.
      *invertible = false;
      layer[v] = 0;
    }
    layers = std::max(layers, layer[v]);
  }

  std::vector<LiftingStep> steps;
  steps.push_back(faces.lift("P_f"));
  steps.push_back(edges.lift("P_e"));
  // Valence-3 layers, deepest first: each reads the coarse values of the layer before it, which
  // later steps overwrite.
  for (int k = layers; k >= 1; --k) {
    std::vector<std::pair<uint32_t, double>> factors;
    StepBuilder vertices;
    for (uint32_t v = 0; v < V; ++v) {
      if (layer[v] != k) continue;
      // x_v = (4/9) sum_j (1 - lambda_j) E_j + (1/9) c_v + (1/9) sum_j lambda_j (c_wj + F_j + F'_j)
      //       - (1/9) sum_faces F, lambda uniform over the neighbours of layer k - 1.
      int earlier = 0;
      for (uint32_t i : edgesAt[v]) {
        const uint32_t w = split.edges[i].a == v ? split.edges[i].b : split.edges[i].a;
        earlier += layer[w] == k - 1;
      }
      const double lambda = 1.0 / earlier;
      factors.emplace_back(v, 1.0 / 9.0);
      for (uint32_t i : edgesAt[v]) {
        const auto& e = split.edges[i];
        const uint32_t w = e.a == v ? e.b : e.a;
        const double lj = layer[w] == k - 1 ? lambda : 0.0;
        vertices.add(v, e.point, 4.0 / 9.0 * (1.0 - lj));
        if (lj != 0.0) {
          vertices.add(v, w, lj / 9.0);
          vertices.add(v, e.face0, lj / 9.0);
          vertices.add(v, e.face1, lj / 9.0);
        }
      }
      for (uint32_t f : facesAt[v]) vertices.add(v, f, -1.0 / 9.0);
    }
    steps.push_back(scalingStep("N_3" + std::to_string(k), std::move(factors)));
    steps.push_back(vertices.lift("P_3" + std::to_string(k)));
  }
  // The other old vertices: x_v = (n-3)/n c_v + 4/n^2 sum E - 1/n^2 sum F (interior, the
  // Catmull-Clark vertex rule written with the new points); x_v = c_v / 2 + (E_1 + E_2) / 4 on the
  // boundary (the rule 1/8, 3/4, 1/8 with the boundary edge points).
  std::vector<std::pair<uint32_t, double>> factors;
  StepBuilder vertices;
  for (uint32_t v = 0; v < V; ++v) {
    if (layer[v] != 0) continue;
    if (onBoundary[v]) {
      factors.emplace_back(v, 0.5);
      for (uint32_t i : edgesAt[v])
        if (split.edges[i].face1 == kNone) vertices.add(v, split.edges[i].point, 0.25);
      continue;
    }
    const double n = double(edgesAt[v].size());
    factors.emplace_back(v, (n - 3.0) / n);
    for (uint32_t i : edgesAt[v]) vertices.add(v, split.edges[i].point, 4.0 / (n * n));
    for (uint32_t f : facesAt[v]) vertices.add(v, f, -1.0 / (n * n));
  }
  steps.push_back(scalingStep("N_v", std::move(factors)));
  steps.push_back(vertices.lift("P_v"));
  return steps;
}

WaveletTransform catmullClarkTransform(const QuadHierarchy& q, int* lowestLevel) {
  std::vector<std::vector<LiftingStep>> steps;
  int lowest = 0;
  for (int l = 1; l <= q.levels(); ++l) {
    bool invertible = true;
    steps.push_back(catmullClarkLevel(q, l, &invertible));
    if (!invertible) lowest = l;
  }
  if (lowestLevel) *lowestLevel = lowest;
  SchemeOptions options;
  options.kind = SchemeKind::CatmullClark;
  options.alpha = options.beta = 0;
  return WaveletTransform(q.h, options, std::move(steps));
}

}  // namespace mrvol
