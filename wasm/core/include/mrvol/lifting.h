// Lifting steps as data, and the wavelet transform of a semi-regular hierarchy as a list of them.
//
// A step is either a lift, x_t += sum_s w_ts x_s, where the targets t and the sources s are
// disjoint sets of vertices (one parity reads the other), or a scaling, x_t *= f_t. So every step
// runs in place, forward (synthesis), inverse (analysis) and transposed (outwards application, the
// adjoint used for volume tensors and gradients). A scheme is the list of its steps per level.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mrvol/hierarchy.h"

namespace mrvol {

struct LiftingStep {
  std::string name;  // the paper's phase: "U", "P_o", "N", "P_e" (Loop); "U", "P" (Butterfly, linear)
  bool scaling = false;
  std::vector<uint32_t> targets;  // rows
  std::vector<uint32_t> offsets;  // lift: row r reads sources[offsets[r] .. offsets[r+1])
  std::vector<uint32_t> sources;
  std::vector<double> weights;    // lift: one per source; scaling: one factor per target
  // A lift that reads only the details of its level before any step has written the odd
  // vertices: it does nothing in a zero-detail synthesis (Loop's and Butterfly's U).
  bool readsOnlyDetails = false;

  size_t entryCount() const { return scaling ? targets.size() : sources.size(); }

  // Per-vertex data with `stride` doubles per vertex (3 for positions).
  void forward(double* x, int stride = 3) const;     // x_t += W x_s   | x_t *= f
  void inverse(double* x, int stride = 3) const;     // x_t -= W x_s   | x_t /= f
  void transposed(double* x, int stride = 3) const;  // x_s += W^T x_t | x_t *= f
};

// CatmullClark: quad hierarchies only (quad_lifting.h).
enum class SchemeKind { Loop, Butterfly, Linear, CatmullClark };

struct SchemeOptions {
  SchemeKind kind = SchemeKind::Loop;
  // Loop update weights (method section 2): derived by least squares, regular setting.
  double alpha = -1.70943;
  double beta = 0.42954;
};

const char* schemeName(SchemeKind kind);
SchemeKind parseSchemeName(const std::string& name);  // "loop" | "butterfly" | "linear" | "catmull-clark"; throws

// Loop boundary update weights (quoted from the WTT project's Loop wavelet code).
constexpr double kLoopBoundaryUpdateEnd = -0.525336;
constexpr double kLoopBoundaryUpdateBeyond = 0.189068;

// The filter bank of a hierarchy. Coefficients are per-vertex 3-vectors in hierarchy numbering:
// at level e, vertices of depth <= e hold coarse coefficients c^e, the others details d^e..d^{n-1}.
class WaveletTransform {
 public:
  WaveletTransform(const Hierarchy& hierarchy, const SchemeOptions& options);
  // A transform whose steps were built elsewhere (steps[l - 1]: synthesis of level l), such as
  // the Catmull-Clark levels of a quad hierarchy (quad_lifting.h).
  WaveletTransform(const Hierarchy& hierarchy, const SchemeOptions& options, std::vector<std::vector<LiftingStep>> steps);

  const Hierarchy& hierarchy() const { return *hierarchy_; }
  const SchemeOptions& options() const { return options_; }
  int levels() const { return hierarchy_->levels; }
  // Synthesis steps from level l-1 to level l, in the order they apply (1 <= l <= n).
  const std::vector<LiftingStep>& synthesisSteps(int l) const { return steps_[l - 1]; }

  // In place on 3 * N doubles in hierarchy order.
  void analyze(double* x, int toLevel) const;       // fine -> level e coefficients
  void synthesize(double* x, int fromLevel) const;  // level e coefficients -> fine positions
  // The same when every detail of levels e..n-1 is zero (subdivision): skips the steps that read
  // only details. The detail entries of x are not read, only overwritten: they need no zeroing.
  void synthesizeZeroDetails(double* x, int fromLevel) const;
  // The adjoint of synthesis (transposed steps, outwards): a per-fine-vertex covector (for example
  // the volume gradient) to the corresponding covector of the level-e coefficients.
  // With details = false only the coarse part (depth <= e) of the result is wanted: the steps that
  // would only write detail entries (the transposes of readsOnlyDetails steps) are skipped.
  void synthesisAdjoint(double* g, int toLevel, int stride = 3, bool details = true) const;

 private:
  const Hierarchy* hierarchy_;
  SchemeOptions options_;
  std::vector<std::vector<LiftingStep>> steps_;
  // Per level: the step a zero-detail synthesis runs as an assignment (x_t = W x_s), or -1 when
  // none can be, and the details of that level are zeroed first.
  std::vector<int> zeroDetailAssign_;
  void prepare();  // readsOnlyDetails and zeroDetailAssign_ from the steps
};

// Mask weights, exposed for tests and teaching views.
double loopEta(int valence);  // 3/8 + cos(2 pi / n) / 4
double loopK(int valence);    // 8/5 eta^2
double loopMu(int valence);   // (1 - K) / n

}  // namespace mrvol
