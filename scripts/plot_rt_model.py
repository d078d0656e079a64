#!/usr/bin/python3
"""The RT model against the paper (issue 39): predicted vs measured speedup, one point per cell.

usage: /usr/bin/python3 scripts/plot_rt_model.py OUT.png RESULTS.json [LABEL=RESULTS.json ...]

Each results.json is a `masq bench --suite fig3 [--suite table1]` run. Plotted per run:
fig3's 16 cells, each predicted by the prices fitted WITHOUT it (leave-one-out, the
figures the fig3 suite writes as rt_model.per_cell), and, where table1 ran, its
out-of-sample predictions of the paper's Table 1 (primary rays). The diagonal is a
perfect prediction; nothing is fitted here, the script only draws what masq wrote.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def runs(args):
    for a in args:
        label, _, path = a.rpartition("=")
        with open(path) as f:
            yield label or path, json.load(f)["suites"]


def main(out, args):
    fig, ax = plt.subplots(figsize=(6.2, 6.2))
    markers = iter("os^Dv<>")
    hi = 1.0
    for label, suites in runs(args):
        m = next(markers)
        rt = suites["fig3"]["data"]["rt_model"]
        cells = rt.get("per_cell", [])
        xs = [c["measured"] for c in cells]
        ys = [c["left_out"] for c in cells]
        ax.scatter(xs, ys, marker=m, label=f"{label} fig3, left out (median {100 * rt['loo_median_rel_error']:.1f}%, "
                   f"worst {100 * rt['loo_max_rel_error']:.0f}%)")
        hi = max([hi] + xs + ys)
        pred = suites.get("table1", {}).get("data", {}).get("rt_model_prediction", [])
        if pred:
            xs = [p["paper_speedup"] for p in pred]
            ys = [p["rt_model_primary"] for p in pred]
            ax.scatter(xs, ys, marker=m, facecolors="none", edgecolors="C3",
                       label=f"{label} Table 1 (out of sample, stand-in scenes)")
            for p, x, y in zip(pred, xs, ys):
                ax.annotate(p["variant"], (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
            hi = max([hi] + xs + ys)
    hi *= 1.1
    ax.plot([0.8, hi], [0.8, hi], color="gray", lw=1, label="predicted = measured")
    ax.set_xlim(0.8, hi)
    ax.set_ylim(0.8, hi)
    ax.set_xlabel("paper's speedup masq/ref (RTX 8000)")
    ax.set_ylabel("RT model's predicted speedup cost(ref)/cost(masq)")
    ax.set_title("RT model vs the masquerade paper (issue 39)")
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
