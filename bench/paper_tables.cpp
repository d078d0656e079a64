#include "bench/paper_tables.h"
#include "bench/bench_report.h"
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numeric>

namespace masq {

namespace {

std::string fig3_column_label(int n, float r) { return fmt::format("N={} r={:g}", n, r); }

const Fig3Measured* find_cell(const std::vector<Fig3Measured>& cells, int n, float r, double tilt) {
  for (const Fig3Measured& c : cells)
    if (c.n == n && c.r == r && c.tilt == tilt) return &c;
  return nullptr;
}

// One masq source's value in a cell: the RT model ("") or a backend's measured speedup.
std::optional<double> masq_value(const Fig3Measured& c, const std::string& source) {
  if (source.empty()) return c.rt_model > 0 ? std::optional<double>(c.rt_model) : std::nullopt;
  auto it = c.speedup.find(source);
  if (it == c.speedup.end() || !(it->second > 0)) return std::nullopt;
  return it->second;
}

std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<std::size_t> idx(v.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::vector<double> rank(v.size());
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t j = i;
    while (j + 1 < idx.size() && v[idx[j + 1]] == v[idx[i]]) ++j;
    for (std::size_t k = i; k <= j; ++k) rank[idx[k]] = 0.5 * double(i + j);
    i = j + 1;
  }
  return rank;
}

std::string rate_text(double v) { return v >= 1e6 ? fmt::format("{:.1f}M", v / 1e6) : fmt::format("{:.1f}K", v / 1e3); }

std::string paper_rate_cell(const PaperRate& r) {
  if (!r.measured) return "n/a (over 16M instances)";
  return fmt::format("{} -> {} ({:.2f}x)", rate_text(r.ref), rate_text(r.ours), r.speedup);
}

std::string stands_for(const HairCase& c) { return c.stands_for.empty() ? "-" : c.stands_for; }

const BenchRow* sized_row(const HairCase& c, Method m) {
  for (const BenchRow& r : c.rows)
    if (r.method == m && r.accel_bytes > 0) return &r;
  return nullptr;
}

std::string mib(double bytes) { return fmt::format("{:.2f} MiB", bytes / 1048576.0); }

// Two figures within 5% of each other are a tie: the paper's OBB and SCB rows of Rings
// differ by 2%, less than what changing the scene or the image moves them by.
constexpr double kTie = 0.05;
bool tie(double a, double b) { return std::abs(a - b) <= kTie * std::max(std::abs(a), std::abs(b)); }

// The order of the paper's five volume types by one figure, "OBB ~ SCB p=0.2 < ..." (~: a tie).
std::string order_text(const std::array<double, 5>& v) {
  std::array<std::size_t, 5> idx{0, 1, 2, 3, 4};
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::string s = kPaperBvTypes[idx[0]];
  for (std::size_t i = 1; i < idx.size(); ++i)
    s += std::string(tie(v[idx[i]], v[idx[i - 1]]) ? " ~ " : " < ") + kPaperBvTypes[idx[i]];
  return s;
}

// "agrees", or how far the two orders agree: the pairs of types ordered alike (a pair
// either side ties counts as alike) and those ordered the other way round.
std::string order_verdict(const std::array<double, 5>& paper, const std::array<double, 5>& masq) {
  int alike = 0;
  std::string differ;
  for (std::size_t i = 0; i < 5; ++i)
    for (std::size_t j = i + 1; j < 5; ++j) {
      if (tie(paper[i], paper[j]) || tie(masq[i], masq[j]) || (paper[i] < paper[j]) == (masq[i] < masq[j])) {
        ++alike;
        continue;
      }
      differ += fmt::format("{}{} vs {}", differ.empty() ? "" : ", ", kPaperBvTypes[i], kPaperBvTypes[j]);
    }
  if (alike == 10) return "agrees";
  return fmt::format("{}: {} of 10 pairs ordered alike; differs on {}", alike >= 7 ? "partly agrees" : "disagrees",
                     alike, differ);
}

// masq's figures of the paper's five types, in kPaperBvTypes order; false when one is missing.
bool masq_five(const std::vector<BvMeasured>& measured, std::array<std::array<double, 5>, 3>& out) {
  for (std::size_t k = 0; k < kPaperBvTypes.size(); ++k) {
    auto it = std::find_if(measured.begin(), measured.end(), [&](const BvMeasured& m) { return m.label == kPaperBvTypes[k]; });
    if (it == measured.end() || !it->ok) return false;
    out[0][k] = it->nb;
    out[1][k] = it->nt;
    out[2][k] = it->t;
  }
  return true;
}

std::optional<std::size_t> paper_type_index(const std::string& label) {
  for (std::size_t k = 0; k < kPaperBvTypes.size(); ++k)
    if (label == kPaperBvTypes[k]) return k;
  return std::nullopt;
}

} // namespace

double rank_correlation(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.size() < 2) return 0.0;
  std::vector<double> ra = ranks(a), rb = ranks(b);
  const double ma = std::accumulate(ra.begin(), ra.end(), 0.0) / double(ra.size());
  const double mb = std::accumulate(rb.begin(), rb.end(), 0.0) / double(rb.size());
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - ma) * (rb[i] - mb);
    saa += (ra[i] - ma) * (ra[i] - ma);
    sbb += (rb[i] - mb) * (rb[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

Table fig3_paper_grid(const std::vector<Fig3Measured>& cells, const std::vector<std::string>& backends) {
  Table t;
  t.title = "the paper's Fig. 3 grid beside masq's: speedup masq/ref per tilt and (N, r)";
  t.header = {"tilt", "source"};
  for (const PaperFig3Column& c : paper_fig3()) t.header.push_back(fig3_column_label(c.n, c.r));
  t.left_columns = 2;
  std::vector<std::string> sources = {""}; // "": the RT model
  sources.insert(sources.end(), backends.begin(), backends.end());
  for (std::size_t ti = 0; ti < kPaperFig3Tilts.size(); ++ti) {
    const double tilt = kPaperFig3Tilts[ti];
    std::vector<std::string> paper_line = {fmt::format("{:g}", tilt), "paper (RTX 8000)"};
    for (const PaperFig3Column& c : paper_fig3()) paper_line.push_back(fmt::format("{:.2f}x", c.speedup[ti]));
    t.add(paper_line);
    for (const std::string& s : sources) {
      std::vector<std::string> line = {"", s.empty() ? "RT model" : s};
      for (const PaperFig3Column& c : paper_fig3()) {
        const Fig3Measured* m = find_cell(cells, c.n, c.r, tilt);
        std::optional<double> v = m ? masq_value(*m, s) : std::nullopt;
        line.push_back(v ? fmt::format("{:.2f}x", *v) : "-");
      }
      t.add(line);
    }
  }
  // How far each masq row orders the paper's cells as the paper does.
  for (const std::string& s : sources) {
    std::vector<double> paper, ours;
    std::vector<std::string> where;
    for (const PaperFig3Column& c : paper_fig3())
      for (std::size_t ti = 0; ti < kPaperFig3Tilts.size(); ++ti) {
        const Fig3Measured* m = find_cell(cells, c.n, c.r, kPaperFig3Tilts[ti]);
        std::optional<double> v = m ? masq_value(*m, s) : std::nullopt;
        if (!v) continue;
        paper.push_back(c.speedup[ti]);
        ours.push_back(*v);
        where.push_back(fmt::format("{} tilt {:g}", fig3_column_label(c.n, c.r), kPaperFig3Tilts[ti]));
      }
    if (paper.size() < 2) continue;
    auto top = [](const std::vector<double>& v) { return std::size_t(std::max_element(v.begin(), v.end()) - v.begin()); };
    const std::size_t tp = top(paper), to = top(ours);
    t.notes.push_back(fmt::format("{}: rank correlation with the paper over {} cells {:.2f}; its largest speedup is {} "
                                  "the paper's largest cell ({}: {:.2f}x{})",
                                  s.empty() ? "RT model" : s, paper.size(), rank_correlation(paper, ours),
                                  tp == to ? "in" : "not in", where[tp], ours[tp],
                                  tp == to ? "" : fmt::format("; {:.2f}x at {}", ours[to], where[to])));
  }
  t.notes.push_back("paper: Wald et al. 2020, Fig. 3 (RTX 8000, OptiX 7, hardware traversal); masq's rows: the same "
                    "cells measured here, '-' where this run did not measure the cell; rank correlation: Spearman's, "
                    "1 = the same ordering of cells");
  return t;
}

Table table1_beside_paper(const std::vector<HairCase>& cases, const std::vector<std::string>& backends) {
  Table t;
  t.title = "the paper's Table 1 beside masq's: rays/s ref -> masq (speedup); masq: primary rays, Mrays/s per backend";
  t.header = {"source", "scene", "stands for", "intersector", "size", "RTX 8000"};
  for (const std::string& b : backends) t.header.push_back(b);
  t.left_columns = 5;
  std::vector<std::string> variants;
  for (const PaperTable1Row& p : paper_table1()) variants.push_back(p.intersector);
  for (const HairCase& c : cases)
    if (std::find(variants.begin(), variants.end(), c.variant) == variants.end()) variants.push_back(c.variant);
  for (const std::string& v : variants) {
    for (const PaperTable1Row& p : paper_table1()) {
      if (v != p.intersector) continue;
      for (std::size_t m = 0; m < paper_table1_models().size(); ++m) {
        const PaperModel& model = paper_table1_models()[m];
        t.add({"paper (RTX 8000)", model.name, "", v, model.size, paper_rate_cell(p.rates[m])});
      }
    }
    for (const HairCase& c : cases) {
      if (c.variant != v) continue;
      std::vector<std::string> line = {"masq", c.scene, stands_for(c), v, fmt::format("{} prims", c.primitives), ""};
      for (const std::string& b : backends) {
        const BenchRow* r = find_row(c.rows, b, Method::Ref, RaySet::Primary);
        const BenchRow* q = find_row(c.rows, b, Method::Masq, RaySet::Primary);
        line.push_back(r && q ? fmt::format("{:.2f} -> {:.2f} ({:.2f}x)", r->mrays_per_s(), q->mrays_per_s(),
                                            q->mrays_per_s() / r->mrays_per_s())
                              : "n/a");
      }
      t.add(line);
    }
  }
  t.notes = {"paper: Wald et al. 2020, Table 1 (RTX 8000, 800x800 pixels, 4 paths per pixel: primary and bounce rays "
             "together); its models are not available here, so each masq scene stands for the paper model of its "
             "kind (stands for; '-': none); masq's scenes are smaller (size column)",
             "masq's speedups are of primary rays on devices without RT cores; table1's other tables have shadow and "
             "diffuse rays; roving x1 is masq's own curve intersector, not in the paper"};
  return t;
}

Table table2_beside_paper(const std::vector<HairCase>& cases) {
  Table t;
  t.title = "the paper's Table 2 beside masq's: memory of the reference (paper: naive; masq: ref) and the masquerade";
  t.header = {"source", "scene", "stands for", "intersector", "common", "accel ref", "accel masq", "total ref",
              "total masq", "accel masq/ref", "total +%"};
  t.left_columns = 4;
  for (const PaperTable2Row& p : paper_table2()) {
    std::string common = std::string(p.common_links) + " links";
    if (paper_bytes(p.common_mesh) > 0) common += std::string(" + ") + p.common_mesh + " mesh";
    t.add({"paper (RTX 8000)", p.model, "", "-", common, p.accel_naive, p.accel_ours, p.total_naive, p.total_ours,
           fmt::format("{:.2f}x", paper_bytes(p.accel_ours) / paper_bytes(p.accel_naive)),
           fmt::format("+{}%", p.plus_percent)});
  }
  for (const HairCase& c : cases) {
    const BenchRow* r = sized_row(c, Method::Ref);
    const BenchRow* m = sized_row(c, Method::Masq);
    if (!r || !m) continue;
    const double ref_total = double(r->prim_bytes + r->accel_bytes), masq_total = double(m->prim_bytes + m->accel_bytes);
    t.add({"masq", c.scene, stands_for(c), c.variant, mib(double(r->prim_bytes)), mib(double(r->accel_bytes)),
           mib(double(m->accel_bytes)), mib(ref_total), mib(masq_total),
           fmt::format("{:.2f}x", double(m->accel_bytes) / double(r->accel_bytes)),
           fmt::format("{:+.0f}%", 100.0 * (masq_total / ref_total - 1.0))});
  }
  t.notes = {"paper: Wald et al. 2020, Table 2 (OptiX: about 250 B per instance); its MB and GB are read as MiB and "
             "GiB for the accel ratio; masq: its own arrays (table2's first table), one instance entry per primitive "
             "in masq; SciVis, neurons and DTI are the paper's sci-vis data, not in table1's scenes"};
  return t;
}

std::vector<std::string> bv_paper_counts_row(const PaperBvScene& p, const std::vector<BvMeasured>& measured) {
  std::vector<std::string> cells;
  for (const BvMeasured& m : measured) {
    std::optional<std::size_t> k = paper_type_index(m.label);
    cells.push_back(k ? fmt::format("{:.2f}M", p.bv[*k].nb) : "-");
    cells.push_back(k ? fmt::format("{:.2f}M", p.bv[*k].nt) : "-");
  }
  return cells;
}

std::vector<std::string> bv_paper_times_row(const PaperBvScene& p, const std::vector<BvMeasured>& measured) {
  std::vector<std::string> cells;
  for (const BvMeasured& m : measured) {
    std::optional<std::size_t> k = paper_type_index(m.label);
    cells.push_back(k ? fmt::format("{:.3f} s", p.bv[*k].t) : "-");
  }
  return cells;
}

std::string bv_agreement(const PaperBvScene& p, const std::string& masq_scene, const std::string& masq_size,
                         const std::string& time_backend, const std::vector<BvMeasured>& measured) {
  std::string size = fmt::format("sizes: the paper's {} has {}K triangles, masq's {} has {}", p.name, p.kilo_triangles,
                                 masq_scene, masq_size);
  std::array<std::array<double, 5>, 3> ours{};
  if (!masq_five(measured, ours))
    return fmt::format("{}: masq did not measure all five of the paper's volume types; {}", p.name, size);
  std::array<std::array<double, 5>, 3> paper{};
  for (std::size_t k = 0; k < 5; ++k) {
    paper[0][k] = p.bv[k].nb;
    paper[1][k] = p.bv[k].nt;
    paper[2][k] = p.bv[k].t;
  }
  const std::string names[3] = {"N_b", "N_t", fmt::format("t ({})", time_backend)};
  std::string s = fmt::format("{}: ", p.name);
  for (int f = 0; f < 3; ++f)
    s += fmt::format("{} {} (paper {}; masq {}); ", names[f], order_verdict(paper[f], ours[f]), order_text(paper[f]),
                     order_text(ours[f]));
  return s + size;
}

} // namespace masq
