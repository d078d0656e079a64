#include "bench/paper_figures.h"
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace masq {

namespace {

constexpr PaperFig3Column kFig3[] = {
    {1, 0.1f, {1.05, 1.16, 1.10, 1.12}},
    {10, 0.01f, {1.03, 1.16, 1.21, 1.22}},
    {100, 0.002f, {1.04, 2.01, 1.91, 1.90}},
    {1000, 0.002f, {1.04, 3.83, 3.32, 3.20}},
};

constexpr PaperModel kModels[] = {
    {"single curl", "600K segs"},
    {"curly hair", "3.3M segs"},
    {"autumn", "3.4M segs + 904K tris"},
    {"franck", "2.2M segs + 250K tris"},
};

constexpr PaperRate rate(double ref, double ours, double speedup) { return {true, ref, ours, speedup}; }
constexpr PaperRate kNa{};
constexpr double K = 1e3, M = 1e6;

constexpr PaperTable1Row kTable1[] = {
    {"capsule", {rate(4.1 * M, 15.8 * M, 3.82), rate(15.5 * M, 49.2 * M, 3.17), rate(106.2 * M, 209.6 * M, 1.97),
                 rate(46.2 * M, 128.8 * M, 2.79)}},
    {"link", {rate(4.2 * M, 16.8 * M, 4.03), rate(15.0 * M, 48.9 * M, 3.27), rate(87.1 * M, 129.3 * M, 1.48),
              rate(45.6 * M, 111.9 * M, 2.46)}},
    {"phantom x1", {rate(81.3 * K, 141.2 * K, 1.74), rate(1.0 * M, 2.2 * M, 2.06), rate(8.8 * M, 52.3 * M, 5.92),
                    rate(2.4 * M, 2.3 * M, 0.99)}},
    {"phantom x2", {rate(343.0 * K, 813.8 * K, 2.37), rate(3.7 * M, 10.0 * M, 2.73), rate(26.6 * M, 123.5 * M, 4.65),
                    rate(6.4 * M, 10.1 * M, 1.59)}},
    {"phantom x4", {rate(1.3 * M, 4.4 * M, 3.44), rate(12.2 * M, 35.3 * M, 2.88), rate(68.4 * M, 144.3 * M, 2.11),
                    rate(18.7 * M, 37.1 * M, 1.98)}},
    {"phantom x8", {rate(5.0 * M, 18.2 * M, 3.65), kNa, kNa, kNa}},
};

constexpr PaperTable2Row kTable2[] = {
    {"SciVis", "7.44 MB", "9.04 MB", "11.8 MB", "71.4 MB", "28.2 MB", "87.8 MB", 211},
    {"neurons", "107 MB", "0", "168 MB", "0.99 GB", "275 MB", "1.1 GB", 311},
    {"DTI", "1.1 MB", "0", "1.76 MB", "10.7 MB", "2.87 MB", "11.8 MB", 310},
    {"autumn", "234 MB", "12.4 MB", "369 MB", "2.2 GB", "615 MB", "2.43 GB", 304},
    {"franck", "167 MB", "13.8 MB", "264 MB", "1.6 GB", "445 MB", "1.74 GB", 302},
};

constexpr PaperBvScene kBv[] = {
    {"Echinodermania II", 124.3,
     {{{2.043, 21.24, 1.24}, {2.045, 20.97, 1.26}, {2.190, 31.46, 4.51}, {4.668, 29.89, 5.48}, {3.418, 38.45, 9.64}}}},
    {"Knots", 44.8,
     {{{1.463, 14.67, 0.68}, {1.437, 14.17, 0.65}, {1.980, 25.53, 5.16}, {2.384, 17.63, 1.30}, {1.837, 24.75, 4.10}}}},
    {"Bars", 0.6,
     {{{5.896, 28.31, 19.71}, {4.100, 21.77, 12.04}, {16.644, 85.38, 80.02}, {1.357, 7.70, 1.24}, {0.809, 8.18, 1.25}}}},
    {"Conference", 282.8,
     {{{4.555, 35.43, 7.86}, {3.917, 32.94, 5.91}, {14.172, 118.17, 62.16}, {3.558, 26.59, 2.61}, {2.044, 28.28, 4.87}}}},
    {"Rings", 554.4,
     {{{19.945, 161.42, 30.34}, {18.500, 159.86, 23.63}, {41.355, 324.06, 179.39}, {19.680, 156.43, 7.88},
       {22.601, 187.24, 83.33}}}},
    {"Bunny", 69.5,
     {{{1.302, 14.60, 0.63}, {1.291, 14.44, 0.63}, {1.494, 24.43, 2.49}, {1.989, 14.97, 1.07}, {1.139, 17.30, 1.76}}}},
    {"Tree", 540.5,
     {{{1.751, 16.60, 1.87}, {1.694, 16.62, 1.47}, {3.339, 31.70, 11.08}, {2.910, 16.52, 3.07}, {2.434, 20.32, 6.26}}}},
};

} // namespace

std::span<const PaperFig3Column> paper_fig3() { return kFig3; }

std::optional<double> paper_fig3_speedup(int n, float r, double tilt_deg) {
  for (const PaperFig3Column& c : kFig3) {
    if (c.n != n || c.r != r) continue;
    for (std::size_t i = 0; i < kPaperFig3Tilts.size(); ++i)
      if (kPaperFig3Tilts[i] == tilt_deg) return c.speedup[i];
  }
  return std::nullopt;
}

std::span<const PaperModel> paper_table1_models() { return kModels; }
std::span<const PaperTable1Row> paper_table1() { return kTable1; }

const PaperModel* paper_model(const std::string& name) {
  for (const PaperModel& m : kModels)
    if (name == m.name) return &m;
  return nullptr;
}

std::span<const PaperTable2Row> paper_table2() { return kTable2; }

double paper_bytes(const char* printed) {
  char* end = nullptr;
  double v = std::strtod(printed, &end);
  while (*end == ' ') ++end;
  if (std::strcmp(end, "GB") == 0) return v * std::ldexp(1.0, 30);
  if (std::strcmp(end, "MB") == 0) return v * std::ldexp(1.0, 20);
  return v; // "0"
}

std::span<const PaperBvScene> paper_bv_table() { return kBv; }

const PaperBvScene* paper_bv_scene(const std::string& name) {
  for (const PaperBvScene& s : kBv)
    if (name == s.name) return &s;
  return nullptr;
}

} // namespace masq
