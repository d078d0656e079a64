#!/usr/bin/python3
"""Plots of a results document written by `masq bench --suite ...` (OUT/results.json).

usage: /usr/bin/python3 scripts/plot_results.py OUT   (Debian python3-matplotlib)

Writes, next to RESULTS.md, one PNG per suite that ran:
  fig3_speedup.png   speedup masq/ref per cell and backend, beside the paper's, the RT model and the call ratio
  table1_speedup.png speedup masq/ref per hair scene x intersector, backend and ray set
  memory.png         table2: ref and masq totals (common + acceleration data) per case
  error_vs_time.png  run time against error of the curve intersector variants
RESULTS.md already links them; a plot whose suite did not run is skipped.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_error import plot_error_rows  # noqa: E402


def speedup(results, backend, ray_set="primary"):
    by_method = {}
    for r in results:
        if r.get("backend") == backend and r.get("rays") == ray_set and "unavailable" not in r:
            by_method[r["method"]] = r.get("mrays_per_s", 0.0)
    if by_method.get("ref", 0) > 0 and by_method.get("masq", 0) > 0:
        return by_method["masq"] / by_method["ref"]
    return None


def backends_of(cases):
    seen = []
    for c in cases:
        for r in c.get("results", []):
            if r.get("backend") not in seen and r.get("backend") != "-":
                seen.append(r["backend"])
    return seen


def grid(ax, values, rows, cols, title, vmax):
    im = ax.imshow(values, cmap="RdYlGn", vmin=0.0, vmax=vmax, aspect="auto")
    ax.set_xticks(range(len(cols)), cols)
    ax.set_yticks(range(len(rows)), rows)
    ax.set_title(title, fontsize=9)
    for i, row in enumerate(values):
        for j, v in enumerate(row):
            ax.text(j, i, "n/a" if v != v else f"{v:.2f}", ha="center", va="center", fontsize=7)
    return im


def plot_fig3(suite, out):
    cells = suite["data"]["cells"]
    rows = []
    for c in cells:
        key = f"N={c['n']} r={c['r']:.3g}"
        if key not in rows:
            rows.append(key)
    tilts = sorted({c["tilt_deg"] for c in cells})
    backends = backends_of(cells)
    # The paper's own Fig. 3 first (null outside its grid; older results hold text).
    paper = lambda c: c.get("paper_rtx_speedup") if isinstance(c.get("paper_rtx_speedup"), (int, float)) else float("nan")
    panels = [("paper (RTX 8000)", paper), ("RT model", lambda c: c["rt_model_speedup"] or float("nan"))]
    for b in backends:
        panels.append((b, lambda c, b=b: speedup(c["results"], b) or float("nan")))
    fig, axes = plt.subplots(1, len(panels), figsize=(2.6 * len(panels) + 1, 0.45 * len(rows) + 2.2), squeeze=False)
    for ax, (name, value) in zip(axes[0], panels):
        values = [[float("nan")] * len(tilts) for _ in rows]
        for c in cells:
            values[rows.index(f"N={c['n']} r={c['r']:.3g}")][tilts.index(c["tilt_deg"])] = value(c)
        im = grid(ax, values, rows, [f"{t:g}" for t in tilts], name, 4.0)
        ax.set_xlabel("tilt (deg)")
        if ax is not axes[0][0]:
            ax.set_yticks([])
    fig.colorbar(im, ax=axes[0].tolist(), shrink=0.8, label="speedup masq / ref")
    fig.suptitle("Fig. 3 grid: masq vs ref speedup (primary rays)")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    return out


def plot_table1(suite, out):
    cases = suite["data"]["cases"]
    backends = backends_of(cases)
    labels = [f"{c['scene'].split(' (')[0]}\n{c['variant']}" for c in cases]
    sets = ["primary", "shadow", "diffuse"]
    fig, axes = plt.subplots(1, len(sets), figsize=(5 * len(sets), 0.35 * len(cases) + 2.5), squeeze=False)
    for ax, rs in zip(axes[0], sets):
        values = [[speedup(c.get("results", []), b, rs) or float("nan") for b in backends] for c in cases]
        im = grid(ax, values, labels, backends, f"{rs} rays", 3.0)
        if ax is not axes[0][0]:
            ax.set_yticks([])
    fig.colorbar(im, ax=axes[0].tolist(), shrink=0.8, label="speedup masq / ref")
    fig.suptitle("Table 1: masq vs ref on hair and fur")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    return out


def plot_memory(suite, out):
    rows = suite["data"]
    if not rows:
        return None
    mib = 1.0 / 1048576.0
    labels = [f"{r['scene'].split(' (')[0]}\n{r['variant']}" for r in rows]
    common = [r["common_bytes"] * mib for r in rows]
    ref = [r["ref_accel_bytes"] * mib for r in rows]
    masq = [r["masq_accel_bytes"] * mib for r in rows]
    xs = range(len(rows))
    fig, ax = plt.subplots(figsize=(max(6, 1.3 * len(rows)), 4.5))
    w = 0.38
    ax.bar([x - w / 2 for x in xs], common, w, color="#999999", label="common (primitives)")
    ax.bar([x - w / 2 for x in xs], ref, w, bottom=common, color="#4477aa", label="ref acceleration")
    ax.bar([x + w / 2 for x in xs], common, w, color="#999999")
    ax.bar([x + w / 2 for x in xs], masq, w, bottom=common, color="#ee6677", label="masq acceleration")
    for x, c, r, m in zip(xs, common, ref, masq):
        ax.text(x + w / 2, c + m, f"+{100 * ((c + m) / (c + r) - 1):.0f}%", ha="center", va="bottom", fontsize=7)
    ax.set_xticks(list(xs), labels, fontsize=7)
    ax.set_ylabel("MiB")
    ax.set_title("Table 2: memory per method (left ref, right masq)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    return out


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out_dir = sys.argv[1]
    doc = json.load(open(os.path.join(out_dir, "results.json")))
    suites = doc.get("suites", {})
    jobs = [("fig3", "fig3_speedup.png", plot_fig3), ("table1", "table1_speedup.png", plot_table1),
            ("table2", "memory.png", plot_memory)]
    for name, file, fn in jobs:
        if name in suites:
            path = fn(suites[name], os.path.join(out_dir, file))
            if path:
                print("wrote", path)
    if "error" in suites:
        rows = [r for r in suites["error"]["data"] if "unavailable" not in r]
        if rows:
            path = os.path.join(out_dir, "error_vs_time.png")
            plot_error_rows(rows, path)
            print("wrote", path)


if __name__ == "__main__":
    main()
