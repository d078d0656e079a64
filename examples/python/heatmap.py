#!/usr/bin/env python3
"""Loads a hair file, traces its camera rays on every backend that opens here with the
paper's reference (ref) and with masquerade (masq), and shows how many times each pixel's
ray called an intersector: the picture of why masquerade pays off on thin, slanted
strands.

    PYTHONPATH=build/python python3 examples/python/heatmap.py ../shared/data/hair/tressfx3_bear.tfx
"""
import argparse

import matplotlib
import numpy as np

import masq


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("file", help="a hair file (.tfx, .hair) or any scene masq.Scene.load reads")
    p.add_argument("--size", type=int, nargs=2, default=[320, 240], metavar=("W", "H"))
    p.add_argument("--out", default="heatmap.png", help="the figure (default heatmap.png)")
    p.add_argument("--show", action="store_true", help="also open a window")
    args = p.parse_args()
    if not args.show:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scene = masq.Scene.load(args.file)
    width, height = args.size
    rays = scene.camera_rays(width, height)
    backends = masq.available_backends()
    print(f"{args.file}: {scene.primitive_count:,} primitives; {len(rays):,} rays; backends: {', '.join(backends)}")

    methods = ["ref", "masq"]
    accels = {m: masq.Accel.build(scene, method=m) for m in methods}
    calls = {}
    for backend in backends:
        ctx = masq.Context(backend)
        for method in methods:
            hits, stats = ctx.trace(accels[method], rays, stats=True)
            ctx.trace(accels[method], rays)  # without counters: the time to quote
            seconds = ctx.timing["trace_seconds"]
            calls[backend, method] = np.maximum(stats["isect_calls"], 0).reshape(height, width)
            print(f"  {backend:10s} {method:4s} {len(rays) / seconds / 1e6:7.2f} Mrays/s, "
                  f"{calls[backend, method].mean():6.2f} intersector calls per ray, "
                  f"{np.mean(hits['prim'] >= 0):.1%} of rays hit")

    # One colour scale for every panel, so ref and masq compare by eye.
    top = np.log1p(max(c.max() for c in calls.values()))
    fig, axes = plt.subplots(len(backends), len(methods), figsize=(4.2 * len(methods), 3.2 * len(backends)),
                             squeeze=False, layout="constrained")
    for row, backend in enumerate(backends):
        for col, method in enumerate(methods):
            c = calls[backend, method]
            ax = axes[row][col]
            im = ax.imshow(np.log1p(c), cmap="inferno", vmin=0, vmax=top)
            ax.set_title(f"{backend}, {method}: {c.mean():.2f} calls/ray", fontsize=9)
            ax.axis("off")
    fig.colorbar(im, ax=axes, fraction=0.03, label="log(1 + intersector calls)")
    fig.suptitle(f"intersector calls per pixel: {args.file.split('/')[-1]}")
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")
    if args.show:
        plt.show()


if __name__ == "__main__":
    main()
