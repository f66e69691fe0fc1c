#!/usr/bin/env python3
"""fairsurf's triangular solves against libigl's min_quad_with_fixed.

fairsurf: cubic triangular patches over an a x b grid of unit squares (each
cut into two triangles, 2ab patches), vertices on a smooth bump, boundary
fixed, stretch 0.1 + bend 1 (Veltkamp & Wesselink), with no continuity
conditions (C0) and with G1 at the vertices; the scene goes through
`fairsurf solve --json` and its own report's total time (assembly,
factorization, the double-double check and every measure of the report).

libigl: the biharmonic energy of a triangle mesh, Q = L^T M^-1 L with the
cotangent Laplacian L and the Voronoi mass matrix M, boundary fixed,
`igl.min_quad_with_fixed` for x, y and z at once, on a k x k vertex grid
whose interior has about as many vertices as fairsurf has free control
points: the same number of unknowns. Timed in its own process with
time.perf_counter from the mesh to the solution (Laplacian, mass matrix, Q,
precomputation, solve).

Both run REPEATS times, alternating, each in a fresh process; the peak
resident memory of each process is read from wait4. Prints time, time per
unknown, peak memory and the ratio libigl / fairsurf of the time per
unknown (> 1: fairsurf is faster).

    python3 -m venv target/bench-venv && target/bench-venv/bin/pip install numpy scipy libigl
    cargo build --release -p fairsurf-cli
    target/bench-venv/bin/python bench/triangle_vs_libigl.py [--grid 80x63] [--repeats 3]
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

PEER = r"""
import sys, time, json
import numpy as np, scipy.sparse as sp, igl
k = int(sys.argv[1])
x = np.linspace(0.0, 1.0, k)
u, v = np.meshgrid(x, x, indexing="ij")
V = np.stack([u.ravel() * k, v.ravel() * k, 0.2 * k * np.sin(3 * u.ravel()) * np.cos(2 * v.ravel() + 0.5)], 1)
idx = np.arange(k * k).reshape(k, k)
a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
F = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int64)
boundary = np.unique(np.concatenate([idx[0], idx[-1], idx[:, 0], idx[:, -1]])).astype(np.int64)
t = time.perf_counter()
L = igl.cotmatrix(V, F)
M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)
Q = (L.T @ sp.diags(1.0 / M.diagonal()) @ L).tocsc()
Z = igl.min_quad_with_fixed(Q, np.zeros((k * k, 3)), boundary, V[boundary], sp.csc_matrix((0, k * k)), np.zeros((0, 3)), True)
seconds = time.perf_counter() - t
assert np.isfinite(Z).all()
print(json.dumps({"seconds": seconds, "unknowns": 3 * (k * k - len(boundary))}))
"""


def peak_mb(cmd):
    """Runs cmd in a child and returns (stdout, its peak resident memory in MB)."""
    pid = os.fork()
    if pid == 0:
        fd = os.open(os.path.join(tempfile.gettempdir(), f"peer-{os.getpid()}.out"), os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
        os.dup2(fd, 1)
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 2)
        try:
            os.execvp(cmd[0], cmd)
        finally:
            os._exit(127)
    _, status, usage = os.wait4(pid, 0)
    path = os.path.join(tempfile.gettempdir(), f"peer-{pid}.out")
    with open(path) as f:
        out = f.read()
    os.remove(path)
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"{' '.join(cmd[:3])} failed (status {status})")
    return out, usage.ru_maxrss / 1024.0


def scene(a, b, vertices_g1):
    verts, tris = [], []
    for j in range(b + 1):
        for i in range(a + 1):
            x, y = i / a, j / b
            verts.append([float(i), float(j), 0.2 * a * math.sin(3 * x) * math.cos(2 * y + 0.5)])
    ident = lambda i, j: j * (a + 1) + i
    for j in range(b):
        for i in range(a):
            tris.append([ident(i, j), ident(i + 1, j), ident(i + 1, j + 1)])
            tris.append([ident(i, j), ident(i + 1, j + 1), ident(i, j + 1)])
    return {
        "name": f"{2 * a * b} cubic patches, {'G1 at the vertices' if vertices_g1 else 'C0'}",
        "surface": {"type": "triangular", "degree": 3, "vertices": verts, "triangles": tris},
        "fix_boundary": True,
        "energy": {"stretch": 0.1, "bend": 1},
        "continuity": {"vertices": vertices_g1, "edges": "off"},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--grid", default="80x63")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--binary", default="target/release/fairsurf")
    ap.add_argument("--g1", action="store_true", help="also G1 at the vertices")
    a = ap.parse_args()
    if not os.path.exists(a.binary):
        sys.exit(f"{a.binary} not found: cargo build --release -p fairsurf-cli")
    ga, gb = (int(s) for s in a.grid.split("x"))
    print(f"fairsurf {a.binary}; libigl via {sys.executable}; median of {a.repeats}, alternating")
    print(f"{'problem':<34}{'unknowns':>10}{'time s':>9}{'us/unknown':>12}{'peak MB':>9}{'ratio':>8}")
    with tempfile.TemporaryDirectory() as tmp:
        for g1 in [False, True] if a.g1 else [False]:
            path = os.path.join(tmp, "scene.json")
            with open(path, "w") as f:
                json.dump(scene(ga, gb, g1), f)
            ours, peer, our_mem, peer_mem = [], [], [], []
            k = None
            for _ in range(a.repeats):
                out, mb = peak_mb([a.binary, "solve", path, "--json"])
                r = json.loads(out)
                ours.append(r["timings_s"]["total"])
                our_mem.append(mb)
                unknowns = r["unknowns"]
                if k is None:
                    # Interior (k − 2)² vertices × 3 ≈ fairsurf's unknowns.
                    k = round(math.sqrt(unknowns / 3)) + 2
                out, mb = peak_mb([sys.executable, "-c", PEER, str(k)])
                p = json.loads(out)
                peer.append(p["seconds"])
                peer_mem.append(mb)
            t_ours, t_peer = statistics.median(ours), statistics.median(peer)
            per_ours, per_peer = t_ours / unknowns, t_peer / p["unknowns"]
            name = f"fairsurf {2 * ga * gb} cubic, {'G1 vertices' if g1 else 'C0'}"
            print(f"{name:<34}{unknowns:>10}{t_ours:>9.3f}{1e6 * per_ours:>12.2f}{max(our_mem):>9.0f}{per_peer / per_ours:>8.2f}")
            name = f"libigl biharmonic {k}x{k}"
            print(f"{name:<34}{p['unknowns']:>10}{t_peer:>9.3f}{1e6 * per_peer:>12.2f}{max(peer_mem):>9.0f}")


if __name__ == "__main__":
    main()
