// The papers' figures beside masq's (bench/paper_figures.h, bench/paper_tables.h): the
// paper values are all there, and the tables and agreement sentences built from given
// (not timed) masq figures say what those figures say.
#include "bench/paper_figures.h"
#include "bench/paper_tables.h"
#include <gtest/gtest.h>

using namespace masq;

namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

int rows_starting(const Table& t, const std::string& source) {
  int n = 0;
  for (const auto& r : t.rows) n += !r.empty() && r[0] == source;
  return n;
}

BenchRow timed_row(const std::string& backend, Method m, double seconds, std::size_t accel, std::size_t prims) {
  BenchRow r;
  r.backend = backend;
  r.method = m;
  r.ray_set = RaySet::Primary;
  r.rays = 1e6;
  r.median_s = seconds;
  r.accel_bytes = accel;
  r.prim_bytes = prims;
  return r;
}

} // namespace

TEST(PaperFigures, Fig3GridHasTheFourColumnsAndEveryTilt) {
  ASSERT_EQ(paper_fig3().size(), 4u);
  EXPECT_EQ(paper_fig3()[0].n, 1);
  EXPECT_EQ(paper_fig3()[0].r, 0.1f);
  EXPECT_EQ(paper_fig3_speedup(1, 0.1f, 0.0), 1.05);
  EXPECT_EQ(paper_fig3_speedup(1, 0.1f, 45.0), 1.12);
  EXPECT_EQ(paper_fig3_speedup(1000, 0.002f, 15.0), 3.83);
  EXPECT_EQ(paper_fig3_speedup(10, 0.01f, 0.0), 1.03);
  EXPECT_FALSE(paper_fig3_speedup(100, 0.005f, 0.0)); // masq's full grid has it, the paper's does not
  EXPECT_FALSE(paper_fig3_speedup(1, 0.1f, 60.0));
}

TEST(PaperFigures, TablesHoldEveryModelAndVolumeType) {
  EXPECT_EQ(paper_table1().size(), 6u); // capsule, link, phantom x1/x2/x4/x8
  EXPECT_EQ(paper_table1_models().size(), 4u);
  EXPECT_FALSE(paper_table1()[5].rates[1].measured); // phantom x8 over OptiX's instance limit
  EXPECT_EQ(paper_table2().size(), 5u);
  EXPECT_NEAR(paper_bytes("0.99 GB") / paper_bytes("168 MB"), 0.99 * 1024 / 168, 1e-12);
  EXPECT_EQ(paper_bytes("0"), 0.0);
  EXPECT_EQ(paper_bv_table().size(), 7u);
  for (const char* s : {"Rings", "Bunny", "Tree"}) EXPECT_NE(paper_bv_scene(s), nullptr) << s;
  EXPECT_EQ(paper_bv_scene("Neuron"), nullptr);
  for (const char* m : {"autumn", "curly hair"}) EXPECT_NE(paper_model(m), nullptr) << m; // masq's stand-ins
}

TEST(PaperTables, RankCorrelation) {
  EXPECT_DOUBLE_EQ(rank_correlation({1, 2, 3, 4}, {10, 20, 30, 40}), 1.0);
  EXPECT_DOUBLE_EQ(rank_correlation({1, 2, 3, 4}, {4, 3, 2, 1}), -1.0);
  EXPECT_DOUBLE_EQ(rank_correlation({1, 1, 1}, {1, 2, 3}), 0.0);
  EXPECT_NEAR(rank_correlation({1, 2, 2, 3}, {1, 2, 3, 4}), 0.9486832980505138, 1e-12); // shared ranks
}

// Every cell of the paper's grid, masq's cpu row at twice the paper's speedup (the same
// order), the RT model at the paper's own: the layout, every paper value, and the notes.
TEST(PaperTables, Fig3GridPutsThePapersValueInEveryCell) {
  std::vector<Fig3Measured> cells;
  for (const PaperFig3Column& c : paper_fig3())
    for (std::size_t i = 0; i < kPaperFig3Tilts.size(); ++i)
      cells.push_back({c.n, c.r, kPaperFig3Tilts[i], c.speedup[i], {{"cpu", 2.0 * c.speedup[i]}}});
  cells.pop_back(); // N=1000 r=0.002 tilt 45 not measured
  Table t = fig3_paper_grid(cells, {"cpu", "vulkan"});
  ASSERT_EQ(t.header.size(), 6u);
  EXPECT_EQ(t.header[2], "N=1 r=0.1");
  EXPECT_EQ(t.header[5], "N=1000 r=0.002");
  ASSERT_EQ(t.rows.size(), 4u * 4u); // per tilt: paper, RT model, cpu, vulkan
  EXPECT_EQ(t.rows[0], (std::vector<std::string>{"0", "paper (RTX 8000)", "1.05x", "1.03x", "1.04x", "1.04x"}));
  EXPECT_EQ(t.rows[4], (std::vector<std::string>{"15", "paper (RTX 8000)", "1.16x", "1.16x", "2.01x", "3.83x"}));
  EXPECT_EQ(t.rows[6], (std::vector<std::string>{"", "cpu", "2.32x", "2.32x", "4.02x", "7.66x"})); // 2 x paper
  EXPECT_EQ(t.rows[14].back(), "-");                                                           // cpu, tilt 45, N=1000
  EXPECT_EQ(t.rows[15], (std::vector<std::string>{"", "vulkan", "-", "-", "-", "-"}));
  std::string notes;
  for (const std::string& n : t.notes) notes += n + "\n";
  EXPECT_TRUE(has(notes, "RT model: rank correlation with the paper over 15 cells 1.00; its largest speedup is in "
                        "the paper's largest cell (N=1000 r=0.002 tilt 15: 3.83x)"))
      << notes;
  EXPECT_TRUE(has(notes, "cpu: rank correlation with the paper over 15 cells 1.00")) << notes;
  EXPECT_FALSE(has(notes, "vulkan:")) << notes; // nothing measured: no claim

  cells[0].speedup["cpu"] = 100.0; // N=1 r=0.1 tilt 0 now masq's largest
  notes.clear();
  for (const std::string& n : fig3_paper_grid(cells, {"cpu"}).notes) notes += n + "\n";
  EXPECT_TRUE(has(notes, "cpu: rank correlation with the paper over 15 cells 0.76")) << notes; // no longer 1
  EXPECT_TRUE(has(notes, "its largest speedup is not in the paper's largest cell (N=1000 r=0.002 tilt 15: 7.66x; "
                         "100.00x at N=1 r=0.1 tilt 0)"))
      << notes;
}

TEST(PaperTables, Table1PutsReferenceRowsBesideMasqs) {
  HairCase c;
  c.scene = "bear fur";
  c.variant = "capsule";
  c.stands_for = "autumn";
  c.primitives = 1000;
  c.rows = {timed_row("cpu", Method::Ref, 1.0, 100, 100), timed_row("cpu", Method::Masq, 0.5, 300, 100)};
  HairCase roving = c;
  roving.variant = "roving x1";
  roving.stands_for = "";
  Table t = table1_beside_paper({c, roving}, {"cpu"});
  EXPECT_EQ(rows_starting(t, "paper (RTX 8000)"), 6 * 4); // every intersector x model, masq ran or not
  EXPECT_EQ(rows_starting(t, "masq"), 2);
  const std::vector<std::string> capsule_curl = {"paper (RTX 8000)", "single curl", "", "capsule", "600K segs",
                                                 "4.1M -> 15.8M (3.82x)"};
  EXPECT_EQ(t.rows[0], capsule_curl);
  EXPECT_EQ(t.rows[4], (std::vector<std::string>{"masq", "bear fur", "autumn", "capsule", "1000 prims", "",
                                                 "1.00 -> 2.00 (2.00x)"}));
  EXPECT_EQ(t.rows.back()[2], "-"); // roving: stands for no paper model
  EXPECT_EQ(t.rows.back()[3], "roving x1");
  bool na = false;
  for (const auto& r : t.rows) na |= r.size() > 5 && r[3] == "phantom x8" && has(r[5], "n/a");
  EXPECT_TRUE(na);
}

TEST(PaperTables, Table2PutsReferenceRowsBesideMasqs) {
  HairCase c;
  c.scene = "bear fur";
  c.variant = "capsule";
  c.stands_for = "autumn";
  c.rows = {timed_row("cpu", Method::Ref, 1.0, 1 << 20, 1 << 20), timed_row("cpu", Method::Masq, 1.0, 3 << 20, 1 << 20)};
  Table t = table2_beside_paper({c});
  ASSERT_EQ(rows_starting(t, "paper (RTX 8000)"), 5);
  EXPECT_EQ(t.rows[0], (std::vector<std::string>{"paper (RTX 8000)", "SciVis", "", "-", "7.44 MB links + 9.04 MB mesh",
                                                 "11.8 MB", "71.4 MB", "28.2 MB", "87.8 MB", "6.05x", "+211%"}));
  EXPECT_EQ(t.rows[1][4], "107 MB links"); // no mesh
  ASSERT_EQ(rows_starting(t, "masq"), 1);
  EXPECT_EQ(t.rows[5], (std::vector<std::string>{"masq", "bear fur", "autumn", "capsule", "1.00 MiB", "1.00 MiB",
                                                 "3.00 MiB", "2.00 MiB", "4.00 MiB", "3.00x", "+100%"}));
}

namespace {
// masq's figures for the paper's five types as the paper's Rings, scaled: the same order.
std::vector<BvMeasured> rings_like(double scale) {
  const PaperBvScene& p = *paper_bv_scene("Rings");
  std::vector<BvMeasured> m;
  for (std::size_t k = 0; k < kPaperBvTypes.size(); ++k)
    m.push_back({kPaperBvTypes[k], true, scale * p.bv[k].nb, scale * p.bv[k].nt, scale * p.bv[k].t});
  m.push_back({"AABB (binned SAH)", true, 1, 1, 1});
  return m;
}
} // namespace

TEST(PaperTables, BvReferenceRowsFollowTheSuitesColumns) {
  const PaperBvScene& p = *paper_bv_scene("Rings");
  std::vector<BvMeasured> m = rings_like(1e-3);
  EXPECT_EQ(bv_paper_counts_row(p, m),
            (std::vector<std::string>{"161.42M", "30.34M", "159.86M", "23.63M", "324.06M", "179.39M", "156.43M", "7.88M",
                                      "187.24M", "83.33M", "-", "-"}));
  EXPECT_EQ(bv_paper_times_row(p, m),
            (std::vector<std::string>{"19.945 s", "18.500 s", "41.355 s", "19.680 s", "22.601 s", "-"}));
}

TEST(PaperTables, BvAgreementSaysWhereTheOrdersDiffer) {
  const PaperBvScene& p = *paper_bv_scene("Rings");
  std::string same = bv_agreement(p, "Rings (SPD rings sf7)", "100 primitives", "cpu", rings_like(1e-3));
  // OBB and both SCBs lie within 5% of each other in the paper's Rings: ties.
  EXPECT_TRUE(has(same, "N_b agrees (paper OBB ~ SCB p=0.2 ~ SCB p=0 < AABB < ball")) << same;
  EXPECT_TRUE(has(same, "N_t agrees (paper OBB < SCB p=0.2 < SCB p=0 < AABB < ball")) << same;
  EXPECT_TRUE(has(same, "t (cpu) agrees")) << same;
  EXPECT_TRUE(has(same, "the paper's Rings has 554.4K triangles, masq's Rings (SPD rings sf7) has 100 primitives")) << same;

  std::vector<BvMeasured> m = rings_like(1e-3);
  std::swap(m[2].nb, m[3].nb); // masq: ball as low as the SCBs, OBB the worst
  std::string flipped = bv_agreement(p, "Rings", "100 primitives", "cpu", m);
  EXPECT_TRUE(has(flipped, "N_b partly agrees: 7 of 10 pairs ordered alike; differs on ball vs OBB, ball vs AABB, "
                           "OBB vs AABB (paper"))
      << flipped;
  m = rings_like(1e-3);
  std::swap(m[0].nt, m[1].nt); // SCB p=0 and p=0.2 swap places, 22% apart
  std::string near = bv_agreement(p, "Rings", "100 primitives", "cpu", m);
  EXPECT_TRUE(has(near, "N_t partly agrees: 9 of 10 pairs ordered alike; differs on SCB p=0 vs SCB p=0.2")) << near;
  m = rings_like(1e-3);
  for (BvMeasured& b : m) b.t = 1.0 / b.t; // the reverse order
  std::string reversed = bv_agreement(p, "Rings", "100 primitives", "cpu", m);
  EXPECT_TRUE(has(reversed, "t (cpu) disagrees: ")) << reversed;

  m = rings_like(1e-3);
  m[4].ok = false; // AABB failed
  EXPECT_TRUE(has(bv_agreement(p, "Rings", "100 primitives", "cpu", m), "did not measure all five"));
}
