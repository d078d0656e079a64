// The source papers' own figures, as data: the one place in the code that holds them
// (copied from ../shared/papers/tables.md, which cites each table). The suites print
// them beside masq's measurements (bench/paper_tables.h); nothing else types a paper
// value.
#pragma once
#include <array>
#include <optional>
#include <span>
#include <string>

namespace masq {

// ---- Wald et al. 2020, Fig. 3: speedup of masquerade over the reference, RTX 8000 ----
inline constexpr std::array<double, 4> kPaperFig3Tilts = {0.0, 15.0, 30.0, 45.0};
struct PaperFig3Column {
  int n;       // cylinders in the bundle
  float r;     // cylinder radius
  std::array<double, 4> speedup; // per kPaperFig3Tilts
};
std::span<const PaperFig3Column> paper_fig3();
// The paper's speedup for one cell of its grid; nullopt where the paper has no such cell.
std::optional<double> paper_fig3_speedup(int n, float r, double tilt_deg);

// ---- Wald et al. 2020, Table 1: rays/s, ref -> ours, RTX 8000, 800x800, 4 paths/pixel ----
struct PaperModel {
  const char* name;     // "curly hair"
  const char* size;     // "3.3M segs", as the paper gives it
};
std::span<const PaperModel> paper_table1_models();
struct PaperRate {
  bool measured = false; // false: n/a (over OptiX's 16M instance limit)
  double ref = 0, ours = 0; // rays/s
  double speedup = 0;       // as printed by the paper (its ratio of unrounded rates)
};
struct PaperTable1Row {
  const char* intersector; // masq's variant name: "capsule", "link", "phantom x1".."phantom x8"
  std::array<PaperRate, 4> rates; // per paper_table1_models()
};
std::span<const PaperTable1Row> paper_table1();
const PaperModel* paper_model(const std::string& name); // nullptr: no such model

// ---- Wald et al. 2020, Table 2: memory, reference (naive) vs masquerade (ours) ----
struct PaperTable2Row {
  const char* model;
  const char* common_links;   // as printed ("7.44 MB", "0.99 GB")
  const char* common_mesh;
  const char* accel_naive;
  const char* accel_ours;
  const char* total_naive;
  const char* total_ours;
  int plus_percent;           // the paper's "+" column: total ours over total naive
};
std::span<const PaperTable2Row> paper_table2();
// "0.99 GB" -> bytes (the paper's MB and GB read as 2^20 and 2^30 bytes; its text does
// not say which, and the ratios move by at most 2.4% between the two readings).
double paper_bytes(const char* printed);

// ---- Kallberg & Larsson 2009, Table 1: single thread, Core 2 Duo T9400 2.53 GHz ----
// The five volume types of their table, in its column order; masq's bv suite names its
// variants the same way.
inline constexpr std::array<const char*, 5> kPaperBvTypes = {"SCB p=0", "SCB p=0.2", "ball", "OBB", "AABB"};
struct PaperBvFigures {
  double t;   // render time, s
  double nb;  // ray/volume tests, millions per image
  double nt;  // ray/triangle tests, millions per image
};
struct PaperBvScene {
  const char* name;          // "Rings"
  double kilo_triangles;     // the paper's tessellation
  std::array<PaperBvFigures, 5> bv; // per kPaperBvTypes
};
std::span<const PaperBvScene> paper_bv_table();
const PaperBvScene* paper_bv_scene(const std::string& name); // nullptr: not in the table

} // namespace masq
