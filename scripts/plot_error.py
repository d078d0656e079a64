#!/usr/bin/python3
"""Plot `masq bench --error --json F` as run time against error (one panel per metric).

usage: /usr/bin/python3 scripts/plot_error.py error.json error.png  (Debian python3-matplotlib)
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def plot_error_rows(rows, out):
    """One scatter panel per error metric, trace time on x, one colour per backend."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    metrics = [("rate", "hit/miss disagreement rate"), ("mean_dt_over_r", "mean |dt| / r")]
    for ax, (key, label) in zip(axes, metrics):
        for backend in sorted({r["backend"] for r in rows}):
            sel = [r for r in rows if r["backend"] == backend]
            xs = [1e3 * r["median_s"] for r in sel]
            ys = [max(r[key], 1e-9) for r in sel]
            ax.scatter(xs, ys, label=backend)
            for r, x, y in zip(sel, xs, ys):
                ax.annotate(r["variant"] + (" *" if r["pareto"] else ""), (x, y), fontsize=6)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("trace time, ms (median)")
        ax.set_ylabel(label + " (floor 1e-9)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle("masq: run time against error (* = Pareto front)")
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    rows = [r for r in json.load(open(sys.argv[1])) if "unavailable" not in r]
    if not rows:
        sys.exit("plot_error: no measured rows in " + sys.argv[1])
    plot_error_rows(rows, sys.argv[2])
    print("wrote", sys.argv[2])


if __name__ == "__main__":
    main()
