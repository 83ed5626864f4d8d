// The cage basis table (rows carried through the synthesis steps) against the zero-detail synthesis
// itself: every column of the table equals the synthesis of one unit cage coordinate to float
// precision, at every level and for every scheme, in the hierarchy's order and in a shuffled one;
// the columns' pattern is the transpose of the rows; applying it equals base + S delta.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "fixtures.h"
#include "shuffled_subdivision.h"
#include "mrvol/cage_basis_table.h"
#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"

using namespace mrvol;

namespace {

void checkTable(const Hierarchy& h, const WaveletTransform& wt, int level, const std::string& where,
                const CageBasisTable* given = nullptr) {
  const size_t n = h.fineVertexCount();
  const uint32_t cage = h.vertexCount[level];
  std::unique_ptr<CageBasisTable> own;
  if (!given) own = std::make_unique<CageBasisTable>(wt, level, h.inputIndex.data());
  const CageBasisTable& table = given ? *given : *own;
  ASSERT_FALSE(table.empty()) << where;
  ASSERT_EQ(table.vertexCount(), n) << where;
  ASSERT_EQ(table.cageSize(), cage) << where;
  // S as a dense matrix from the table's rows (caller's order).
  std::vector<double> fromTable(n * cage, 0.0);
  std::vector<uint32_t> cols;
  std::vector<float> weights;
  size_t entries = 0;
  for (uint32_t v = 0; v < n; ++v) {
    table.row(v, cols, weights);
    entries += cols.size();
    for (size_t k = 0; k < cols.size(); ++k) {
      ASSERT_LT(cols[k], cage) << where;
      fromTable[size_t(v) * cage + cols[k]] += weights[k];
      // The column of cols[k] lists v.
      ASSERT_TRUE(std::find(table.columnBegin(cols[k]), table.columnEnd(cols[k]), v) != table.columnEnd(cols[k])) << where;
    }
  }
  EXPECT_EQ(entries, table.entryCount()) << where;
  size_t columnEntries = 0;
  for (uint32_t c = 0; c < cage; ++c) columnEntries += size_t(table.columnEnd(c) - table.columnBegin(c));
  EXPECT_EQ(columnEntries, table.entryCount()) << where;
  // Each unit cage coordinate synthesized.
  double worst = 0.0;
  std::vector<double> x(3 * n);
  for (uint32_t c = 0; c < cage; ++c) {
    std::fill(x.begin(), x.end(), 0.0);
    x[3 * size_t(c)] = 1.0;
    wt.synthesizeZeroDetails(x.data(), level);
    for (size_t hv = 0; hv < n; ++hv)
      worst = std::max(worst, std::fabs(x[3 * hv] - fromTable[size_t(h.inputIndex[hv]) * cage + c]));
  }
  EXPECT_LT(worst, 1e-6) << where;
  // apply: base + S delta (+ origin), against the same in doubles.
  std::vector<float> base4(4 * n, 0.0f), delta4(4 * size_t(cage), 0.0f), out4(4 * n), out3(3 * n);
  std::vector<uint32_t> outIndex(n);  // the output in reverse order
  for (uint32_t v = 0; v < n; ++v) outIndex[v] = uint32_t(n) - 1 - v;
  const std::vector<double> b = fixtures::randomVector(3 * n, 3), d = fixtures::randomVector(3 * size_t(cage), 5);
  for (size_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) base4[4 * v + k] = float(b[3 * v + k]);
  for (size_t c = 0; c < cage; ++c)
    for (int k = 0; k < 3; ++k) delta4[4 * c + k] = float(d[3 * c + k]);
  const float origin[3] = {1.0f, -2.0f, 0.5f};
  table.apply(base4.data(), delta4.data(), origin, out4.data(), out3.data(), outIndex.data());
  double applyError = 0.0;
  for (size_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) {
      double expected = b[3 * v + k];
      for (uint32_t c = 0; c < cage; ++c) expected += fromTable[v * cage + c] * d[3 * c + k];
      applyError = std::max(applyError, std::fabs(out4[4 * v + k] - expected));
      applyError = std::max(applyError, std::fabs(out3[3 * size_t(outIndex[v]) + k] - (expected + origin[k])));
    }
  EXPECT_LT(applyError, 1e-5) << where;
  // applyRows on every other vertex writes exactly those.
  std::vector<float> some4(4 * n, -7.0f), some3(3 * n, -7.0f);
  std::vector<uint32_t> rows;
  for (uint32_t v = 0; v < n; v += 2) rows.push_back(v);
  table.applyRows(rows.data(), rows.size(), base4.data(), delta4.data(), origin, some4.data(), some3.data(), outIndex.data());
  for (uint32_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) {
      const size_t o = 3 * size_t(outIndex[v]) + k;
      if (v % 2 == 0) {
        EXPECT_EQ(some4[4 * v + k], out4[4 * v + k]) << where << " vertex " << v;
        EXPECT_EQ(some3[o], out3[o]) << where << " vertex " << v;
      } else {
        EXPECT_EQ(some3[o], -7.0f) << where << " vertex " << v;
      }
    }
}

}  // namespace

TEST(CageBasisTable, ColumnsAreTheZeroDetailSynthesisAtEveryLevel) {
  for (const auto& fx : fixtures::baseFixtures()) {
    const Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    for (const SchemeOptions& options : fixtures::allSchemes()) {
      const WaveletTransform wt(h, options);
      for (int level = 0; level < h.levels; ++level)
        checkTable(h, wt, level, fx.name + " " + fixtures::label(options) + " level " + std::to_string(level));
    }
  }
}

TEST(CageBasisTable, RowsInAShuffledOrder) {
  const fixtures::Shuffled shuffled = fixtures::shuffledSubdivision(5);
  const Hierarchy h = Hierarchy::detect(shuffled.mesh);
  const WaveletTransform wt(h, SchemeOptions{});
  for (int level = 0; level < h.levels; ++level) checkTable(h, wt, level, "shuffled level " + std::to_string(level));
}

// The polynomial builder's rows, handed over (basisOut), make a table that passes the same checks,
// with the same entries as the table's own rows (rounded to float once instead of at every step).
TEST(CageBasisTable, FromThePolynomialBuildersRows) {
  for (const auto& fx : fixtures::baseFixtures()) {
    const Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    const WaveletTransform wt(h, SchemeOptions{});
    for (int level = 0; level < h.levels; ++level) {
      const std::string where = fx.name + " handed over, level " + std::to_string(level);
      CageBasis basis;
      const CagePolynomialBuilder builder(wt, level, 8'000'000, &basis);
      ASSERT_EQ(basis.offset.size(), h.fineVertexCount() + 1) << where;
      EXPECT_EQ(basis.index.size(), builder.basisEntries()) << where;
      const CageBasisTable handed(basis, h.vertexCount[level], h.inputIndex.data()), own(wt, level, h.inputIndex.data());
      checkTable(h, wt, level, where, &handed);
      EXPECT_EQ(handed.entryCount(), own.entryCount()) << where;
    }
  }
}

TEST(CageBasisTable, NoTableAtTheFinestLevel) {
  const fixtures::Fixture fx = fixtures::baseFixtures()[0];
  const Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
  const WaveletTransform wt(h, SchemeOptions{});
  EXPECT_TRUE(CageBasisTable(wt, h.levels, h.inputIndex.data()).empty());
}

// apply is base + the row's terms added one by one in float: a small cage's dense rows in cage order,
// a larger cage's sparse rows in the order row() lists them; bit for bit (a dense row's zero weights
// add nothing), from the table's own rows and from the polynomial builder's.
TEST(CageBasisTable, ApplyAddsTheRowsTermsInOrder) {
  for (const auto& fx : fixtures::baseFixtures()) {
    const Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    const WaveletTransform wt(h, SchemeOptions{});
    const size_t n = h.fineVertexCount();
    for (int level = 0; level < h.levels; ++level) {
      const uint32_t cage = h.vertexCount[level];
      CageBasis basis;
      const CagePolynomialBuilder builder(wt, level, 8'000'000, &basis);
      const CageBasisTable own(wt, level, h.inputIndex.data()), handed(basis, cage, h.inputIndex.data());
      for (const CageBasisTable* table : {&own, &handed}) {
        const std::string where = fx.name + " level " + std::to_string(level) + (table == &own ? " own" : " handed");
        EXPECT_EQ(table->dense(), cage <= CageBasisTable::kMaxDenseCage) << where;
        std::vector<float> base4(4 * n, 0.0f), delta4(4 * size_t(cage), 0.0f), out4(4 * n), out3(3 * n);
        std::vector<uint32_t> outIndex(n);
        for (uint32_t v = 0; v < n; ++v) outIndex[v] = v;
        const std::vector<double> b = fixtures::randomVector(3 * n, 7), d = fixtures::randomVector(3 * size_t(cage), 11);
        for (size_t v = 0; v < n; ++v)
          for (int k = 0; k < 3; ++k) base4[4 * v + k] = float(b[3 * v + k]);
        for (size_t c = 0; c < cage; ++c)
          for (int k = 0; k < 3; ++k) delta4[4 * c + k] = float(d[3 * c + k]);
        const float origin[3] = {0.25f, 3.0f, -1.5f};
        table->apply(base4.data(), delta4.data(), origin, out4.data(), out3.data(), outIndex.data());
        std::vector<uint32_t> cols;
        std::vector<float> weights;
        size_t mismatches = 0;
        for (uint32_t v = 0; v < n; ++v) {
          table->row(v, cols, weights);
          for (int k = 0; k < 3; ++k) {
            float p = base4[4 * size_t(v) + k];
            for (size_t e = 0; e < cols.size(); ++e) p += weights[e] * delta4[4 * size_t(cols[e]) + k];
            mismatches += out4[4 * size_t(v) + k] != p || out3[3 * size_t(v) + k] != p + origin[k];
          }
          mismatches += out4[4 * size_t(v) + 3] != 0.0f;
        }
        EXPECT_EQ(mismatches, 0u) << where;
      }
    }
  }
}
