#!/usr/bin/env python3
"""Spy plots of H and of its block L, as the talk draws them, from `ldlpgs spy` files.

Usage: python3 papers/scripts/plot_spy.py SPY.json [SPY.json ...] [--out-dir DIR]
Writes DIR/NAME.png for each SPY.json (default DIR: the file's own directory).

Left, H = J W J^T over the equality constraints in the order the scene lists them: a square
per nonzero block, sized by the blocks' rows. Right, the block L of the factorization in the
ordering's pivot order (lower triangle): the blocks H already has in one colour, the fill
blocks elimination creates in another. The data are the spy file's (apps/spy_command.cpp):
block_sizes and pivots give the scalar coordinates, H_blocks and L_blocks the squares.
"""
import argparse
import json
import os
import sys

from debian_python import require

matplotlib = require("matplotlib", "python3-matplotlib")

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the backend)
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Patch, Rectangle  # noqa: E402

H_COLOUR, FILL_COLOUR, GRID_COLOUR = "#1f4e99", "#d62728", "#dddddd"


def starts(sizes):
    """First scalar row of each block."""
    out, row = [], 0
    for s in sizes:
        out.append(row)
        row += s
    return out


def squares(blocks, sizes, colour):
    """One rectangle per (row block, column block); y grows downwards as in a matrix."""
    first = starts(sizes)
    rects = [Rectangle((first[j], first[i]), sizes[j], sizes[i]) for i, j in blocks]
    return PatchCollection(rects, facecolor=colour, edgecolor="white", linewidth=0.3)


def frame(ax, sizes, title):
    dim = sum(sizes)
    for x in starts(sizes)[1:]:
        ax.axhline(x, color=GRID_COLOUR, linewidth=0.2, zorder=0)
        ax.axvline(x, color=GRID_COLOUR, linewidth=0.2, zorder=0)
    ax.set_xlim(0, dim)
    ax.set_ylim(dim, 0)
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=10)
    ax.tick_params(labelsize=7)


def summary(spy):
    bodies = "1 body" if spy["shattered_bodies"] == 1 else f"{spy['shattered_bodies']} bodies"
    shattered = (f", shattered ({bodies}, {spy['welds']} welds)"
                 if spy["shattered"] else "")
    return (f"{spy['scene']}{shattered}: {spy['constraints']} constraints, dim(H) = {spy.get('n', spy.get('dim'))}, "
            f"density {100 * spy['density']:.1f}%, {spy['ordering']}: {spy['fill_blocks']} fill blocks, "
            f"{spy['flops'] / 1000:.1f}k flops")


def plot(spy, path):
    """Draws one spy file's H and L side by side into `path` (PNG)."""
    pivot_sizes, pivots = spy["block_sizes"], spy["pivots"]
    # H in the scene's constraint order: pivot k is block pivots[k]
    sizes = [0] * len(pivots)
    for k, b in enumerate(pivots):
        sizes[b] = pivot_sizes[k]
    h = []
    for i, j in spy["H_blocks"]:
        h.append((pivots[i], pivots[j]))
        if i != j:
            h.append((pivots[j], pivots[i]))
    l_kept = [(i, j) for i, j, fill in spy["L_blocks"] if not fill]
    l_fill = [(i, j) for i, j, fill in spy["L_blocks"] if fill]

    fig, (ax_h, ax_l) = plt.subplots(1, 2, figsize=(10, 5.4))
    ax_h.add_collection(squares(h, sizes, H_COLOUR))
    frame(ax_h, sizes, "H (constraint order)")
    ax_l.add_collection(squares(l_kept, pivot_sizes, H_COLOUR))
    ax_l.add_collection(squares(l_fill, pivot_sizes, FILL_COLOUR))
    frame(ax_l, pivot_sizes, f"L ({spy['ordering']} pivot order)")
    ax_l.legend(handles=[Patch(color=H_COLOUR, label="block of H"),
                         Patch(color=FILL_COLOUR, label=f"fill ({len(l_fill)} blocks)")],
                loc="upper right", fontsize=8, frameon=True)
    fig.suptitle(summary(spy), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("spy", nargs="+", help="files written by `ldlpgs spy --json-file`")
    parser.add_argument("--out-dir", help="directory of the PNG files (default: beside each spy file)")
    args = parser.parse_args()
    for path in args.spy:
        with open(path) as f:
            spy = json.load(f)
        out_dir = args.out_dir or os.path.dirname(path) or "."
        os.makedirs(out_dir, exist_ok=True)
        png = os.path.join(out_dir, os.path.splitext(os.path.basename(path))[0] + ".png")
        plot(spy, png)
        print(f"{path} -> {png}")


if __name__ == "__main__":
    main()
