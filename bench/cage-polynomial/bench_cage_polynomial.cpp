// mrvol_bench_cage_polynomial: the cage polynomial built from the fine triangles
// (CagePolynomialBuilder) on the spiky ball subdivided to N = 10k .. 655k, against the theta route
// (computeVolumeTensor + VolumeEditor::useTensor) where that fits. One JSON object per line.
//
//   mrvol_bench_cage_polynomial [--levels 5-8] [--cage-levels 0,3] [--scheme loop]
//                               [--theta-max-mb 1500] [--model public/models/spiky-ball.obj] [--markdown]
//
// Meshes: spiky-ball.obj (icosahedron base, n = 3, Loop details) is carried onto
// Hierarchy::subdivide(its base, n) for n = 5..8 (N = 10242 .. 655362) and subdivided further by
// a zero-detail Loop synthesis from level 3: the spiky ball, subdivided.
//
// Per (N, e): the builder's set-up (basis functions, regions, terms: depends on connectivity and
// scheme only) and build (one synthesis of the details, one pass over the regions) in ms (wall
// clock and this thread's CPU time: the machine may be shared), the
// number of terms, the builder's tables and the polynomial in MB, the process's peak RSS, and the
// CPU cost of one evaluate + gradient, one alongDirection and one correction step on the polynomial
// (what VolumeEditor::solveGlobal does per iteration on its tensor path: evaluate with gradient,
// the direction on the free set, alongDirection, Newton on the cubic, the move) in microseconds;
// and the fine positions after such a step (all of the cage moved) by a zero-detail synthesis and
// by the stencil table of cageBasis.
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/mesh.h"
#include "mrvol/volume_editor.h"
#include "mrvol/volume_tensor.h"

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }
volatile double sink = 0;

// CPU time of this thread: the machine may be shared, and the work is single-threaded.
double cpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

double peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

// Median CPU time of f() in microseconds: batches of calls that take at least ~100 us each (the
// clock's resolution and overhead stay out), at least 21 batches and ~200 ms in all.
template <class F>
double medianMicroseconds(F&& f) {
  int perBatch = 1;
  for (;;) {
    const double start = cpuMs();
    for (int i = 0; i < perBatch; ++i) f();
    if ((cpuMs() - start) * 1000 >= 100 || perBatch >= (1 << 20)) break;
    perBatch *= 2;
  }
  std::vector<double> times;
  double spent = 0;
  while (times.size() < 21 || (spent < 200 && times.size() < 1001)) {
    const double start = cpuMs();
    for (int i = 0; i < perBatch; ++i) f();
    const double ms = cpuMs() - start;
    times.push_back(ms * 1000 / perBatch);
    spent += ms;
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

struct Options {
  int minLevel = 5, maxLevel = 8;
  std::vector<int> cageLevels = {0, 3};
  std::string scheme = "loop";
  double thetaMaxMb = 1500;
  std::string model = std::string(MRVOL_SOURCE_DIR) + "/public/models/spiky-ball.obj";
  bool markdown = false;  // also a Markdown table (on stderr) at the end
};

[[noreturn]] void usage(const std::string& message) {
  std::fprintf(stderr, "mrvol_bench_cage_polynomial: %s\nusage: mrvol_bench_cage_polynomial [--levels 5-8] "
               "[--cage-levels 0,3] [--scheme loop] [--theta-max-mb 1500] [--model FILE] [--markdown]\n", message.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage("missing value after " + a);
      return argv[++i];
    };
    if (a == "--levels") {
      const std::string v = value();
      const size_t dash = v.find('-');
      o.minLevel = std::atoi(v.substr(0, dash).c_str());
      o.maxLevel = dash == std::string::npos ? o.minLevel : std::atoi(v.substr(dash + 1).c_str());
      if (o.minLevel < 3 || o.maxLevel > 9 || o.minLevel > o.maxLevel) usage("--levels expects L or L1-L2 within 3..9");
    } else if (a == "--cage-levels") {
      o.cageLevels.clear();
      std::stringstream ss(value());
      for (std::string item; std::getline(ss, item, ',');) o.cageLevels.push_back(std::atoi(item.c_str()));
    } else if (a == "--scheme") {
      o.scheme = value();
    } else if (a == "--theta-max-mb") {
      o.thetaMaxMb = std::atof(value().c_str());
    } else if (a == "--model") {
      o.model = value();
    } else if (a == "--markdown") {
      o.markdown = true;
    } else {
      usage("unknown argument " + a);
    }
  }
  return o;
}

struct Mesh {
  mrvol::Hierarchy h;
  std::vector<double> positions;  // hierarchy order = caller order (subdivide)
};

// The spiky ball (n = 3) carried onto n levels of its base: vertices matched by their ends.
Mesh spikyBall(const std::string& path, int levels) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw mrvol::Error("cannot read " + path);
  std::stringstream text;
  text << in.rdbuf();
  const mrvol::TriangleMesh spiky = mrvol::readObj(text.str());
  const mrvol::Hierarchy detected = mrvol::Hierarchy::detect(spiky, 3);
  if (detected.levels != 3) throw mrvol::Error(path + " is not 3 levels of splits");
  mrvol::TriangleMesh base;
  base.faces = detected.faces[0];
  base.positions.assign(3 * size_t(detected.vertexCount[0]), 0.0);
  Mesh m{mrvol::Hierarchy::subdivide(base, levels), {}};
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> byEnds;
  for (uint32_t v = detected.vertexCount[0]; v < detected.fineVertexCount(); ++v)
    byEnds[{std::min(detected.ends[2 * v], detected.ends[2 * v + 1]), std::max(detected.ends[2 * v], detected.ends[2 * v + 1])}] = v;
  std::vector<uint32_t> match(m.h.vertexCount[3]);
  for (uint32_t v = 0; v < match.size(); ++v) {
    if (v < m.h.vertexCount[0]) { match[v] = v; continue; }
    const uint32_t a = match[m.h.ends[2 * v]], b = match[m.h.ends[2 * v + 1]];
    match[v] = byEnds.at({std::min(a, b), std::max(a, b)});
  }
  std::vector<double> level3(spiky.positions.size());
  detected.toHierarchyOrder(spiky.positions.data(), level3.data());
  m.positions.assign(3 * m.h.fineVertexCount(), 0.0);
  for (uint32_t v = 0; v < match.size(); ++v)
    for (int k = 0; k < 3; ++k) m.positions[3 * v + k] = level3[3 * match[v] + k];
  mrvol::SchemeOptions loop;
  mrvol::WaveletTransform(m.h, loop).synthesizeZeroDetails(m.positions.data(), 3);
  return m;
}

double polynomialMb(const mrvol::CagePolynomial& p) {
  return (p.linear.size() * 8.0 + p.pairI.size() * 8.0 + p.pairQ.size() * 8.0 + p.tripleI.size() * 12.0 +
          p.tripleT.size() * 8.0) / (1 << 20);
}

// One correction step as VolumeEditor::solveGlobal takes it on the tensor path: evaluate with
// gradient, direction = gradient on the free set (all but vertex 0), alongDirection, Newton on the
// cubic from the linearized step, the move.
double correctionStep(const mrvol::CagePolynomial& poly, std::vector<double>& cage, double reference,
                      std::vector<double>& g, std::vector<double>& q) {
  const double v = poly.evaluate(cage.data(), g.data());
  double norm2 = 0;
  for (size_t i = 3; i < g.size(); ++i) norm2 += g[i] * g[i];
  const double step = (reference - v) / norm2;
  std::fill(q.begin(), q.begin() + 3, 0.0);
  std::copy(g.begin() + 3, g.end(), q.begin() + 3);
  double c[4];
  poly.alongDirection(cage.data(), q.data(), c);
  double s = step;
  for (int n = 0; n < 60; ++n) {
    const double f = c[0] + s * (c[1] + s * (c[2] + s * c[3])) - reference;
    const double df = c[1] + s * (2 * c[2] + 3 * s * c[3]);
    if (!(df != 0)) break;
    const double next = s - f / df;
    const bool done = std::fabs(next - s) <= 1e-15 * std::fabs(s);
    s = next;
    if (done) break;
  }
  for (size_t i = 3; i < cage.size(); ++i) cage[i] += s * q[i];
  return c[0] + s * (c[1] + s * (c[2] + s * c[3]));
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  mrvol::SchemeOptions scheme;
  scheme.kind = mrvol::parseSchemeName(o.scheme);
  std::vector<std::string> table;
  char row[1024];
  for (int levels = o.minLevel; levels <= o.maxLevel; ++levels) {
    auto start = Clock::now();
    const Mesh m = spikyBall(o.model, levels);
    const mrvol::WaveletTransform wt(m.h, scheme);
    const double meshMs = msSince(start);
    const mrvol::TriangleMesh fine{m.positions, m.h.fineFaces()};
    const mrvol::Vec3 origin = mrvol::volumeReferencePoint(fine);
    const double volume = mrvol::meshVolume(fine);
    for (int e : o.cageLevels) {
      if (e > levels) continue;
      std::vector<double> x = m.positions;
      wt.analyze(x.data(), e);
      const uint32_t cageSize = m.h.vertexCount[e];
      const double rssBeforeMb = peakRssMb();  // mesh, hierarchy, transform: before the builder
      start = Clock::now();
      double cpu = cpuMs();
      const mrvol::CagePolynomialBuilder builder(wt, e);
      const double setupMs = msSince(start), setupCpuMs = cpuMs() - cpu;
      start = Clock::now();
      cpu = cpuMs();
      const mrvol::CagePolynomial poly = builder.build(x.data());
      const double buildMs = msSince(start), buildCpuMs = cpuMs() - cpu;
      std::vector<double> cage(x.begin(), x.begin() + 3 * size_t(cageSize));
      for (size_t i = 0; i < cage.size(); i += 3) cage[i] -= origin.x, cage[i + 1] -= origin.y, cage[i + 2] -= origin.z;
      const double error = std::fabs(poly.evaluate(cage.data(), nullptr) - volume) / std::fabs(volume);

      std::vector<double> g(cage.size()), direction(cage.size()), q(cage.size());
      for (size_t i = 0; i < direction.size(); ++i) direction[i] = 1e-3 * std::sin(double(i));
      const double evalUs = medianMicroseconds([&] { sink = sink + poly.evaluate(cage.data(), g.data()); });
      const double alongUs = medianMicroseconds([&] {
        double k[4];
        poly.alongDirection(cage.data(), direction.data(), k);
        sink = sink + k[3];
      });
      // Steps towards a volume 0.1% off and back, alternately: each is a real correction.
      std::vector<double> stepCage = cage;
      int flip = 0;
      const double stepUs = medianMicroseconds([&] {
        sink = sink + correctionStep(poly, stepCage, volume * (++flip % 2 ? 1.001 : 1.0), g, q);
      });

      // Fine positions after a step (every free cage vertex moves): a zero-detail synthesis of the
      // cage plus the details' synthesis D, against the stencil table (cageBasis rows) times the cage.
      std::vector<double> positions(x.size());
      const double synthesisUs = medianMicroseconds([&] {
        std::copy(cage.begin(), cage.end(), positions.begin());
        wt.synthesizeZeroDetails(positions.data(), e);
        sink = sink + positions[3];
      });
      const mrvol::CageBasis basis = mrvol::cageBasis(wt, e);
      const double stencilUs = medianMicroseconds([&] {
        const size_t n = m.h.fineVertexCount();
        for (size_t v = 0; v < n; ++v) {
          double p0 = 0, p1 = 0, p2 = 0;
          for (uint64_t k = basis.offset[v]; k < basis.offset[v + 1]; ++k) {
            const double w = basis.value[k], *c = &cage[3 * size_t(basis.index[k])];
            p0 += w * c[0], p1 += w * c[1], p2 += w * c[2];
          }
          positions[3 * v] = p0, positions[3 * v + 1] = p1, positions[3 * v + 2] = p2;
        }
        sink = sink + positions[3];
      });

      std::printf("{\"bench\":\"cage-polynomial\",\"scheme\":\"%s\",\"N\":%zu,\"levels\":%d,\"e\":%d,\"cage\":%u,"
                  "\"regions\":%zu,\"maxRegionCage\":%zu,\"basisEntries\":%zu,\"setupMs\":%.3f,\"setupCpuMs\":%.3f,"
                  "\"buildMs\":%.3f,\"buildCpuMs\":%.3f,"
                  "\"triples\":%zu,\"pairs\":%zu,\"builderMb\":%.2f,\"polynomialMb\":%.3f,\"peakRssBeforeMb\":%.1f,\"peakRssMb\":%.1f,"
                  "\"evaluateGradientUs\":%.3f,\"alongDirectionUs\":%.3f,\"correctionStepUs\":%.3f,"
                  "\"relativeVolumeError\":%.2e,\"meshMs\":%.1f,\"positionsBySynthesisUs\":%.0f,\"positionsByStencilUs\":%.0f}\n",
                  o.scheme.c_str(), m.h.fineVertexCount(), levels, e, cageSize, builder.regionCount(), builder.maxRegionCage(),
                  builder.basisEntries(), setupMs, setupCpuMs, buildMs, buildCpuMs, poly.tripleT.size(), poly.pairI.size(),
                  builder.bytes() / double(1 << 20), polynomialMb(poly), rssBeforeMb, peakRssMb(), evalUs, alongUs, stepUs, error, meshMs, synthesisUs, stencilUs);
      std::fflush(stdout);
      std::snprintf(row, sizeof row, "| %zu | %d | %u | %zu | %.0f / %.0f | %.1f / %.1f | %zu | %zu | %.1f | %.2f | %.0f | %.2f | %.2f | %.2f | %.0e |",
                    m.h.fineVertexCount(), e, cageSize, builder.maxRegionCage(), setupCpuMs, setupMs, buildCpuMs, buildMs,
                    poly.tripleT.size(), poly.pairI.size(), builder.bytes() / double(1 << 20), polynomialMb(poly), peakRssMb(),
                    evalUs, alongUs, stepUs, error);
      table.push_back(row);

      // The theta route, where its estimate fits the memory given.
      const mrvol::TensorEstimate estimate = mrvol::estimateCageTensor(wt, e);
      const double estimateMb = (estimate.bytes + estimate.denseBytes) / double(1 << 20);
      if (estimateMb > o.thetaMaxMb) {
        std::printf("{\"bench\":\"theta-route\",\"scheme\":\"%s\",\"N\":%zu,\"e\":%d,\"skipped\":true,\"estimateMb\":%.0f}\n",
                    o.scheme.c_str(), m.h.fineVertexCount(), e, estimateMb);
        std::fflush(stdout);
        table.back() += " estimate " + std::to_string(int(estimateMb)) + " MB: not run |";
        continue;
      }
      cpu = cpuMs();
      const mrvol::VolumeTensor theta = mrvol::computeVolumeTensor(wt, e, mrvol::TensorStorage::Cage);
      const double thetaCpuMs = cpuMs() - cpu;
      mrvol::VolumeEditor editor(m.h, wt, e, m.positions.data());
      cpu = cpuMs();
      editor.useTensor(theta);
      const double contractCpuMs = cpuMs() - cpu;
      std::vector<double> gradient;
      const double thetaValue = editor.gradientTensor(gradient);
      std::printf("{\"bench\":\"theta-route\",\"scheme\":\"%s\",\"N\":%zu,\"e\":%d,\"thetaCpuMs\":%.1f,\"contractCpuMs\":%.1f,"
                  "\"thetaMb\":%.1f,\"thetaEntries\":%zu,\"peakRssMb\":%.1f,\"valueDifference\":%.2e}\n",
                  o.scheme.c_str(), m.h.fineVertexCount(), e, thetaCpuMs, contractCpuMs, theta.bytes() / double(1 << 20),
                  theta.storedCount(), peakRssMb(), std::fabs(thetaValue - poly.evaluate(cage.data(), nullptr)) / std::fabs(volume));
      std::fflush(stdout);
      std::snprintf(row, sizeof row, " %.0f ms, %.0f MB, peak RSS %.0f MB |", thetaCpuMs + contractCpuMs,
                    theta.bytes() / double(1 << 20), peakRssMb());
      table.back() += row;
    }
  }
  if (o.markdown) {
    std::fprintf(stderr, "| N | e | cage | max s | set-up ms (CPU / wall) | build ms (CPU / wall) | triples | pairs | "
                         "builder MB | polynomial MB | peak RSS MB | evaluate + gradient us | alongDirection us | "
                         "correction step us | volume error | theta route (CPU, tensor, peak RSS) |\n"
                         "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
    for (const auto& r : table) std::fprintf(stderr, "%s\n", r.c_str());
  }
  return 0;
}
