// mrvol_bench: timings of the core on icospheres, one JSON object per line on stdout.
//
// Built twice from this one file: natively by CMake (build/native/mrvol_bench, every bench/*.cpp)
// and with emscripten by bench/run.mjs (build/bench-wasm/mrvol_bench.js, linked to the same
// build/wasm/libmrvol_core.a the WASM module uses), so that the WASM timings are measured inside
// WASM, without the JS API's copies.
//
//   mrvol_bench [--levels 3-8] [--schemes loop,butterfly,linear] [--min-time-ms 400]
//               [--min-reps 5] [--max-reps 2000] [--no-setup]
//
// Lines:
//   {"bench":"env", ...}                          compiler, platform
//   {"bench":"setup","level":L,...}               one-off costs: Hierarchy::subdivide,
//                                                 validateMesh, Hierarchy::detect, per-scheme
//                                                 WaveletTransform construction (ms)
//   {"bench":"transform","scheme":S,"level":L,...} full analysis to level 0 + synthesis back on
//                                                 3N doubles in hierarchy order: median, min, max
//                                                 over reps (ms), vertices per second
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/mesh.h"

#if defined(__EMSCRIPTEN__) && __has_include(<emscripten/version.h>)
#include <emscripten/version.h>
#endif

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Defeats dead-code elimination of benchmarked results.
volatile double sink = 0;

mrvol::TriangleMesh icosahedron() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  mrvol::TriangleMesh m;
  m.positions = {-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t,
                 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1};
  for (size_t i = 0; i < m.positions.size(); i += 3) {
    double l = std::sqrt(m.positions[i] * m.positions[i] + m.positions[i + 1] * m.positions[i + 1] +
                         m.positions[i + 2] * m.positions[i + 2]);
    for (int k = 0; k < 3; ++k) m.positions[i + k] /= l;
  }
  m.faces = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
             3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  return m;
}

struct Options {
  int minLevel = 3, maxLevel = 8;
  std::vector<std::string> schemes = {"loop", "butterfly", "linear"};
  double minTimeMs = 400;
  int minReps = 5, maxReps = 2000;
  bool setup = true;
};

[[noreturn]] void usage(const char* message) {
  std::fprintf(stderr, "mrvol_bench: %s\nusage: mrvol_bench [--levels 3-8] [--schemes loop,butterfly,linear] "
                       "[--min-time-ms 400] [--min-reps 5] [--max-reps 2000] [--no-setup]\n", message);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    if (a == "--levels") {
      std::string v = value();
      size_t dash = v.find('-');
      o.minLevel = std::atoi(v.substr(0, dash).c_str());
      o.maxLevel = dash == std::string::npos ? o.minLevel : std::atoi(v.substr(dash + 1).c_str());
      if (o.minLevel < 0 || o.maxLevel > 10 || o.minLevel > o.maxLevel) usage("--levels expects L or L1-L2 within 0..10");
    } else if (a == "--schemes") {
      o.schemes.clear();
      std::string v = value();
      for (size_t start = 0; start <= v.size();) {
        size_t comma = v.find(',', start);
        if (comma == std::string::npos) comma = v.size();
        o.schemes.push_back(v.substr(start, comma - start));
        start = comma + 1;
      }
    } else if (a == "--min-time-ms") {
      o.minTimeMs = std::atof(value().c_str());
    } else if (a == "--min-reps") {
      o.minReps = std::max(1, std::atoi(value().c_str()));
    } else if (a == "--max-reps") {
      o.maxReps = std::max(1, std::atoi(value().c_str()));
    } else if (a == "--no-setup") {
      o.setup = false;
    } else {
      usage(("unknown argument " + a).c_str());
    }
  }
  o.maxReps = std::max(o.maxReps, o.minReps);
  return o;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Median time of f() over repetitions: at least one, then more while under budgetMs in all and
// maxReps runs (one-off costs of large meshes take seconds: they run once; small ones get a
// median that is not dominated by a first, cold run).
template <class F>
double timeMedian(F&& f, double budgetMs = 300, int maxReps = 5) {
  std::vector<double> times;
  double spent = 0;
  do {
    auto start = Clock::now();
    f();
    times.push_back(msSince(start));
    spent += times.back();
  } while (spent < budgetMs && int(times.size()) < maxReps);
  return median(times);
}

void printEnv() {
  std::string compiler;
#if defined(__EMSCRIPTEN__)
  const char* platform = "wasm";
#if defined(__EMSCRIPTEN_major__)
  compiler = "emscripten " + std::to_string(__EMSCRIPTEN_major__) + "." + std::to_string(__EMSCRIPTEN_minor__) + "." +
             std::to_string(__EMSCRIPTEN_tiny__) + ", clang " + __clang_version__;
#else
  compiler = std::string("emscripten, clang ") + __clang_version__;
#endif
#else
  const char* platform = "native";
#if defined(__clang__)
  compiler = std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  compiler = std::string("g++ ") + __VERSION__;
#endif
#endif
#ifdef NDEBUG
  const bool ndebug = true;
#else
  const bool ndebug = false;
#endif
  for (char& c : compiler)
    if (c == '"' || c == '\\') c = '\'';
  std::printf("{\"bench\":\"env\",\"platform\":\"%s\",\"compiler\":\"%s\",\"ndebug\":%s,\"pointerBits\":%d}\n", platform,
              compiler.c_str(), ndebug ? "true" : "false", int(8 * sizeof(void*)));
}

// The icosphere: zero-detail Loop synthesis (`loop`, a Loop transform of h) of the unit
// icosahedron, every vertex then projected on the unit sphere. Hierarchy order (= subdivision order).
std::vector<double> icospherePositions(const mrvol::WaveletTransform& loop, const mrvol::TriangleMesh& base) {
  std::vector<double> x(3 * loop.hierarchy().fineVertexCount(), 0.0);
  std::copy(base.positions.begin(), base.positions.end(), x.begin());
  loop.synthesize(x.data(), 0);
  for (size_t i = 0; i < x.size(); i += 3) {
    double l = std::sqrt(x[i] * x[i] + x[i + 1] * x[i + 1] + x[i + 2] * x[i + 2]);
    for (int k = 0; k < 3; ++k) x[i + k] /= l;
  }
  return x;
}

void timeTransform(const Options& o, const mrvol::WaveletTransform& transform, const std::string& schemeName,
                   const std::vector<double>& x0) {
  const int level = transform.levels();
  const size_t n = transform.hierarchy().fineVertexCount();
  size_t entries = 0;
  for (int l = 1; l <= level; ++l)
    for (const auto& step : transform.synthesisSteps(l)) entries += step.entryCount();
  std::vector<double> x(x0.size());
  std::vector<double> total, analysis, synthesis;
  // Untimed warm-up, at least 3 runs and 200 ms: memory first touched, caches and branch
  // predictors warm, and under WASM the code optimised (bench/run.mjs runs Node with
  // --no-liftoff, so there is no baseline-compiled phase to wait out).
  auto warm = Clock::now();
  for (int r = 0; r < 3 || msSince(warm) < 200; ++r) {
    std::copy(x0.begin(), x0.end(), x.begin());
    transform.analyze(x.data(), 0);
    transform.synthesize(x.data(), 0);
  }
  double spent = 0;
  while ((int(total.size()) < o.minReps || spent < o.minTimeMs) && int(total.size()) < o.maxReps) {
    std::copy(x0.begin(), x0.end(), x.begin());
    auto a = Clock::now();
    transform.analyze(x.data(), 0);
    auto b = Clock::now();
    transform.synthesize(x.data(), 0);
    auto c = Clock::now();
    double am = std::chrono::duration<double, std::milli>(b - a).count();
    double sm = std::chrono::duration<double, std::milli>(c - b).count();
    analysis.push_back(am), synthesis.push_back(sm), total.push_back(am + sm);
    spent += am + sm;
    sink = sink + x[0];
  }
  double err = 0;
  for (size_t i = 0; i < x.size(); ++i) err = std::max(err, std::fabs(x[i] - x0[i]));
  const double med = median(total);
  std::printf("{\"bench\":\"transform\",\"scheme\":\"%s\",\"level\":%d,\"vertices\":%zu,\"liftingEntries\":%zu,"
              "\"reps\":%zu,\"medianMs\":%.4f,\"minMs\":%.4f,\"maxMs\":%.4f,\"analysisMs\":%.4f,"
              "\"synthesisMs\":%.4f,\"verticesPerSecond\":%.6g,\"roundtripError\":%.3g}\n",
              schemeName.c_str(), level, n, entries, total.size(), med, *std::min_element(total.begin(), total.end()),
              *std::max_element(total.begin(), total.end()), median(analysis), median(synthesis),
              double(n) / (med / 1000.0), err);
  std::fflush(stdout);
}

void run(const Options& o) {
  const mrvol::TriangleMesh base = icosahedron();
  for (int level = o.minLevel; level <= o.maxLevel; ++level) {
    mrvol::Hierarchy h;
    const double subdivideMs = timeMedian([&] { h = mrvol::Hierarchy::subdivide(base, level); });
    const size_t n = h.fineVertexCount();

    // Transforms: Loop first (it also makes the icosphere), construction timed.
    std::vector<std::string> names = o.schemes;
    std::stable_partition(names.begin(), names.end(), [](const std::string& s) { return s == "loop"; });
    if (names.empty() || names[0] != "loop") names.insert(names.begin(), "loop");
    std::vector<std::unique_ptr<mrvol::WaveletTransform>> transforms;
    std::string buildTimes;
    for (const std::string& name : names) {
      mrvol::SchemeOptions scheme;
      scheme.kind = mrvol::parseSchemeName(name);
      std::unique_ptr<mrvol::WaveletTransform> t;
      const double buildMs = timeMedian([&] { t = std::make_unique<mrvol::WaveletTransform>(h, scheme); });
      transforms.push_back(std::move(t));
      buildTimes += ",\"" + name + "TransformMs\":" + std::to_string(buildMs);
    }
    const std::vector<double> x0 = icospherePositions(*transforms[0], base);

    if (o.setup) {
      mrvol::TriangleMesh fine;
      fine.positions = x0;
      fine.faces = h.fineFaces();
      const double validateMs = timeMedian([&] { mrvol::validateMesh(fine); });
      mrvol::Hierarchy detected;
      const double detectMs = timeMedian([&] { detected = mrvol::Hierarchy::detect(fine); });
      if (detected.levels != level) {
        std::fprintf(stderr, "mrvol_bench: detect found %d levels on the level-%d icosphere\n", detected.levels, level);
        std::exit(1);
      }
      std::printf("{\"bench\":\"setup\",\"level\":%d,\"vertices\":%zu,\"faces\":%zu,\"subdivideMs\":%.4f,"
                  "\"validateMs\":%.4f,\"detectMs\":%.4f%s}\n",
                  level, n, h.fineFaces().size() / 3, subdivideMs, validateMs, detectMs, buildTimes.c_str());
      std::fflush(stdout);
    }
    for (size_t k = 0; k < names.size(); ++k)
      if (std::find(o.schemes.begin(), o.schemes.end(), names[k]) != o.schemes.end())
        timeTransform(o, *transforms[k], names[k], x0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o = parse(argc, argv);
  printEnv();
  try {
    run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mrvol_bench: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
