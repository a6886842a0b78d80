#!/usr/bin/env python3
"""How much of each factorization a supernodal path could take: the fundamental
supernodes of our factor's scalar L, in CHOLMOD's sense (columns j and j+1 share one when j+1 is
j's parent and only child in the elimination tree and struct(j) = {j+1} U struct(j+1)), and the
share of the factorization's flops (sum of squared column counts) in supernodes at least 16 and
64 columns wide, where dense BLAS-3 kernels pay (papers/factor.md).

Usage: PYTHONPATH=build/python python3 papers/scripts/supernode_widths.py [build/bin/ldlpgs]
(the Python module of build.sh's build; prints a Markdown table; about 2 s). Scenes are exported
with `ldlpgs export` (shattered as by default, and --no-shatter), factored with ordering meca and
their exported blocks; test matrices with blocks auto.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np
import scipy.sparse as sp

import ldlpgs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LDLPGS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bin", "ldlpgs")
SCENES = ["tracked-vehicle", "multi-wheeled-vehicle", "mechanism-50", "ragdoll"]
MATRICES = ["bcsstk13.mtx", "bcsstk02.mtx", "dwt_992.mtx", "jagmesh7.mtx", "bcsstk01.mtx"]


def widths(path, blocks):
    a = ldlpgs.mmread(path)
    l = sp.csc_matrix(ldlpgs.analyze(a, blocks=blocks, ordering="meca").factorize(a, regularization=1e-8).L())
    n = l.shape[0]
    count = np.diff(l.indptr)  # column counts, diagonal included
    parent = np.full(n, -1)
    for j in range(n):
        rows = l.indices[l.indptr[j]:l.indptr[j + 1]]
        below = rows[rows > j]
        if below.size:
            parent[j] = below.min()
    children = np.bincount(parent[parent >= 0], minlength=n)
    result, w = [], 1
    for j in range(n - 1):
        if parent[j] == j + 1 and children[j + 1] == 1 and count[j] == count[j + 1] + 1:
            w += 1
        else:
            result.append(w)
            w = 1
    result.append(w)
    flops = count.astype(float) ** 2
    column_width = np.repeat(result, result)
    return n, result, flops, column_width


def row(name, path, blocks):
    n, result, flops, column_width = widths(path, blocks)
    total = flops.sum()
    share = lambda w: f"{100 * flops[column_width >= w].sum() / total:.0f} %"
    print(f"| {name} | {n} | {len(result)} | {max(result)} | {share(16)} | {share(64)} | {total:.3g} |")


print("| problem | n | supernodes | widest | flops in supernodes >= 16 wide | >= 64 wide | flops |")
print("|---|---|---|---|---|---|---|")
with tempfile.TemporaryDirectory() as tmp:
    for scene in SCENES:
        for shatter, flag in (("", []), (" --no-shatter", ["--no-shatter"])):
            m, b = os.path.join(tmp, "h.mtx"), os.path.join(tmp, "h.blocks")
            subprocess.run([LDLPGS, "export", scene, *flag, "--matrix-file", m, "--blocks-file", b],
                           check=True, capture_output=True)
            row(scene + shatter, m, b)
for matrix in MATRICES:
    row(matrix, os.path.join(ROOT, "tests", "data", "matrices", matrix), "auto")
