// The papers' figures (bench/paper_figures.h) beside masq's: the tables and generated
// sentences the fig3, table1, table2 and bv suites print. Pure functions of measured
// numbers, so tests check them without running a suite.
#pragma once
#include "bench/paper_figures.h"
#include "bench/suite.h"
#include "bench/table.h"
#include <map>
#include <string>
#include <vector>

namespace masq {

// ---- fig3 ----
struct Fig3Measured {
  int n = 0;
  float r = 0;
  double tilt = 0;
  double rt_model = 0;                    // <= 0: not measured
  std::map<std::string, double> speedup;  // per backend, masq/ref rays/s
};
// The paper's grid in its own layout (rows: tilt, then source; columns: its (N, r)
// pairs): the paper's RTX 8000 row, the RT model's and each backend's measured speedup,
// and a note per masq row saying how far its ordering of the paper's cells agrees.
Table fig3_paper_grid(const std::vector<Fig3Measured>& cells, const std::vector<std::string>& backends);
// Spearman's rank correlation of two equally long lists (ties share their mean rank);
// 0 for fewer than two values or a constant list.
double rank_correlation(const std::vector<double>& a, const std::vector<double>& b);

// ---- table1 and table2 ----
// The paper's Table 1 per intersector: a "paper (RTX 8000)" row per model, then masq's
// rows of that intersector (primary-ray speedups per backend), each naming the paper
// model its scene stands for (HairCase::stands_for, "-": none).
Table table1_beside_paper(const std::vector<HairCase>& cases, const std::vector<std::string>& backends);
// The paper's Table 2 rows (accel and total ratios ours/naive) above masq's (masq/ref).
Table table2_beside_paper(const std::vector<HairCase>& cases);

// ---- bv (Kallberg & Larsson, Table 1) ----
struct BvMeasured {
  std::string label;   // the bv suite's variant label: kPaperBvTypes for the paper's five
  bool ok = false;
  double nb = 0, nt = 0; // per primary ray
  double t = 0;          // seconds, one backend's trace of the image
};
// Cells for the bv suite's counts table and times table, in the order of `measured`:
// the paper's N_b / N_t (millions per image) and t (s), "-" for a variant not in it.
std::vector<std::string> bv_paper_counts_row(const PaperBvScene& p, const std::vector<BvMeasured>& measured);
std::vector<std::string> bv_paper_times_row(const PaperBvScene& p, const std::vector<BvMeasured>& measured);
// One sentence: per N_b, N_t and t, the paper's and masq's order of the five volume
// types and whether they agree: how many of the 10 pairs of types both order alike
// (figures within 5% of each other tie, and a tie on either side counts as alike) and
// which pairs they order the other way round; then the two scenes' sizes.
std::string bv_agreement(const PaperBvScene& p, const std::string& masq_scene, const std::string& masq_size,
                         const std::string& time_backend, const std::vector<BvMeasured>& measured);

} // namespace masq
