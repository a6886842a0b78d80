#!/usr/bin/env python3
"""Compares the elimination orderings on one Matrix Market matrix with the ldlpgs module: loads
it with SciPy, prints nnz(L), flops, block fill and block flops per ordering (what `ldlpgs order`
prints) and saves a bar chart of the flops per ordering.

    PYTHONPATH=build/python python3 examples/compare_orderings.py tests/data/matrices/bcsstk13.mtx --plot-file flops.png
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt
import scipy.io

import ldlpgs

DEFAULT = pathlib.Path(__file__).resolve().parents[1] / "tests" / "data" / "matrices" / "494_bus.mtx"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("matrix", nargs="?", default=str(DEFAULT), help="Matrix Market file (symmetric)")
    parser.add_argument("--blocks", default="auto", help="auto, a block size, or a partition file")
    parser.add_argument("--orderings", default="all", help="comma-separated ordering names, or all")
    parser.add_argument("--plot-file", default="orderings_flops.png", help="the bar chart (PNG)")
    args = parser.parse_args()

    a = scipy.io.mmread(args.matrix)
    blocks = int(args.blocks) if args.blocks.isdigit() else args.blocks
    results = ldlpgs.order(a, blocks=blocks, orderings=args.orderings)

    print(f"{pathlib.Path(args.matrix).name}: n = {a.shape[0]}, nnz(A) = {a.nnz}")
    print(f"{'ordering':<13} {'nnz(L)':>10} {'flops':>12} {'block fill':>11} {'block flops':>12} {'time ms':>8}")
    dash = "-"
    for name, r in results.items():
        fill = dash if r["block_fill_edges"] is None else r["block_fill_edges"]
        block_flops = dash if r["block_flops"] is None else f"{r['block_flops']:.0f}"
        print(f"{name:<13} {r['nnz_L']:>10} {r['flops']:>12.0f} {fill:>11} {block_flops:>12} {r['ordering_ms']:>8.2f}")

    # Scalar flops (as CHOLMOD counts them) for every ordering; the best one stands out.
    names = list(results)
    flops = [results[n]["flops"] for n in names]
    best = min(flops)
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.bar(names, flops, color=["tab:green" if f == best else "tab:blue" for f in flops])
    ax.set_yscale("log")  # the natural order can cost orders of magnitude more than the rest
    ax.set_ylabel("flops of the LDL^T (CHOLMOD's count)")
    ax.set_title(f"{pathlib.Path(args.matrix).name}: flops per ordering")
    ax.tick_params(axis="x", rotation=30)
    fig.tight_layout()
    fig.savefig(args.plot_file, dpi=100)
    print(f"wrote {args.plot_file}")


if __name__ == "__main__":
    main()
