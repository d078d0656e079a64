#!/usr/bin/python3
"""Plots of a merged report written by `masq report RUN.json ... --out DIR` (DIR/report.json).

usage: /usr/bin/python3 scripts/plot_report.py DIR   (Debian python3-matplotlib)

Writes, next to DIR/RESULTS.md, one PNG per suite whose tables hold ratios: report_<suite>.png,
the suite's first such table (report.json names it: "plot", "plot_table") as grouped bars, one
group per row and one bar per device (each cell's first ratio, e.g. the speedup masq/ref).
RESULTS.md already links them.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

REPORT_FORMAT = ("masq-report", 1)  # bench/report_doc.h: report_format, report_format_version


def is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def row_labels(table):
    """Each row's label cells joined, a number with its column's name ("N=1000 r=0.002 tilt=15",
    "bear fur (TressFX 3) capsule"); an empty cell repeats the row above's."""
    left = table["label_columns"]
    names = table["header"][:left]
    labels, above = [], [""] * left
    for row in table["rows"]:
        cells = [row[i] if i < len(row) and row[i] else above[i] for i in range(left)]
        above = cells
        labels.append(" ".join(f"{n}={c}" if is_number(c) else c for n, c in zip(names, cells) if c))
    return labels


def plot_suite(suite, table, out_path):
    labels = row_labels(table)
    columns = [c for c in table["device_columns"] if any(v is not None for v in c["ratios"])]
    n = len(columns)
    width = 0.8 / max(n, 1)
    fig, ax = plt.subplots(figsize=(max(6.0, 0.32 * len(labels) * max(n, 2) + 2), 4.2))
    for i, c in enumerate(columns):
        xs = [k + (i - (n - 1) / 2) * width for k in range(len(labels))]
        ys = [v if v is not None else 0.0 for v in c["ratios"]]
        header = table["header"][c["column"]]
        ax.bar(xs, ys, width, label=header)
    ax.axhline(1.0, color="black", linewidth=0.8)
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels, rotation=60, ha="right", fontsize=7)
    ax.set_ylabel("ratio (first in each cell)")
    ax.set_title(f"{suite['name']}: {table['title']}", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out_path, dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_report.py DIR   (DIR/report.json from masq report)")
    path = os.path.join(sys.argv[1], "report.json")
    with open(path) as f:
        report = json.load(f)
    if (report.get("format"), report.get("format_version")) != REPORT_FORMAT:
        sys.exit(f"{path}: not a masq report of format {REPORT_FORMAT[0]} version {REPORT_FORMAT[1]}")
    for suite in report["suites"]:
        if suite.get("plot") is None:
            continue
        out_path = os.path.join(sys.argv[1], suite["plot"])
        plot_suite(suite, suite["tables"][suite["plot_table"]], out_path)
        print(f"wrote {out_path}")


if __name__ == "__main__":
    main()
