#!/usr/bin/env python3
"""fairsurf's B-spline thin plate against a plain scipy sparse solve.

The problem (issue 19, item 6): a bicubic B-spline of c x c control points
over uniform knots on [0, 1]^2, the net on a wavy sheet at the Greville
points, two rings fixed, the inner (c - 4)^2 points free, the thin plate
1/2 int |R_uu|^2 + 2|R_uv|^2 + |R_vv|^2 minimized.

fairsurf: `fairsurf solve scene.json --json` in its own process, its
report's total time (assembly, sparse Cholesky, refinement, the two roads to
the written net's energy and the excess check) and the process's peak
resident memory.

The peer is what a scipy user writes: the 1-D Gram matrices
M_r[i, k] = int N_i^(r) N_k^(r) by Gauss-Legendre with p + 1 nodes per span
(exact), derivatives from scipy.interpolate.BSpline, the Hessian
M_2 (x) M_0 + 2 M_1 (x) M_1 + M_0 (x) M_2 by scipy.sparse.kron, the fixed
points moved to the right-hand side, one sparse LU (SuperLU, `splu`) solved
for x, y and z. Timed in its own process with time.perf_counter from the
knots to the net; its peak memory read from wait4 like fairsurf's. The two
nets are compared (max |dP| over the free points).

Both run REPEATS times, alternating, each in a fresh process. Prints time,
peak memory and the ratio peer time / fairsurf time (> 1: fairsurf faster).
With --lambda L the fairsurf rows add a bicubic normal field (lambda = L,
the coordinates coupled) and the peer is left out (it has no such term).

    python3 -m venv target/bench-venv && target/bench-venv/bin/pip install numpy scipy
    cargo build --release -p fairsurf-cli
    target/bench-venv/bin/python bench/bspline_vs_scipy.py [--counts 50,100,200] [--repeats 3]
"""

import argparse
import json
import math
import os
import statistics
import sys
import tempfile

PEER = r"""
import sys, time, json
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla
from scipy.interpolate import BSpline
scene = json.load(open(sys.argv[1]))
s = scene["surface"]
p = s["degree"][0]
knots = np.array(s["knots"][0])
net = s["control_points"]
c = len(net)
t = time.perf_counter()
def gram(r):
    edges = np.unique(knots)
    x, w = np.polynomial.legendre.leggauss(p + 1)
    a, b = edges[:-1, None], edges[1:, None]
    pts = (a + (b - a) * (x[None, :] + 1) / 2).ravel()
    wts = ((b - a) / 2 * w[None, :]).ravel()
    basis = BSpline(knots, np.eye(c), p)
    B = basis.derivative(r)(pts) if r else basis(pts)
    return sp.csr_matrix((B * wts[:, None]).T @ B)
M0, M1, M2 = gram(0), gram(1), gram(2)
H = (sp.kron(M2, M0) + 2 * sp.kron(M1, M1) + sp.kron(M0, M2)).tocsr()
P = np.array([[q if q is not None else [0.0, 0.0, 0.0] for q in row] for row in net]).reshape(c * c, 3)
free = np.array([i * c + j for i in range(c) for j in range(c) if net[i][j] is None])
known = np.setdiff1d(np.arange(c * c), free)
Hff = H[free][:, free].tocsc()
rhs = -(H[free][:, known] @ P[known])
X = spla.splu(Hff).solve(rhs)
seconds = time.perf_counter() - t
P[free] = X
assert np.isfinite(X).all()
print(json.dumps({"seconds": seconds, "unknowns": 3 * len(free), "net": P.tolist()}))
"""


def peak_mb(cmd):
    """Runs cmd in a child and returns (stdout, its peak resident memory in MB)."""
    pid = os.fork()
    if pid == 0:
        fd = os.open(os.path.join(tempfile.gettempdir(), f"peer-{os.getpid()}.out"),
                     os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
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


def scene(c, lam):
    """Bicubic, c x c control points, uniform knots, two rings of a wavy
    sheet fixed, the thin plate (and a bicubic normal field when lam > 0)."""
    p, spans = 3, c - 3
    knots = [0.0] * (p + 1) + [k / spans for k in range(1, spans)] + [1.0] * (p + 1)
    grev = [sum(knots[i + 1:i + p + 1]) / p for i in range(c)]
    wave = lambda x, y: 0.2 * math.sin(2.5 * math.pi * x) * math.cos(1.5 * math.pi * y) + 0.3 * x * y
    net = [[[grev[i], grev[j], wave(grev[i], grev[j])] if min(i, j, c - 1 - i, c - 1 - j) < 2 else None
            for j in range(c)] for i in range(c)]
    energy = {"bend": 1}
    if lam > 0:
        field = [[[0.3 * (i / 3 - 0.5), -0.2 * (j / 3 - 0.5), 1.0] for j in range(4)] for i in range(4)]
        energy["normal_field"] = {"weight": lam, "degree": [3, 3], "control_points": field}
    return {"surface": {"type": "bspline", "degree": [p, p], "knots": [knots, knots],
                        "control_points": net},
            "fixed_rings": 2, "energy": energy}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--counts", default="50,100,200")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--lambda", dest="lam", type=float, default=0.0)
    ap.add_argument("--binary", default="target/release/fairsurf")
    a = ap.parse_args()
    if not os.path.exists(a.binary):
        sys.exit(f"{a.binary} not found: cargo build --release -p fairsurf-cli")
    peer = a.lam == 0
    print(f"fairsurf {a.binary}; scipy via {sys.executable}; median of {a.repeats}, alternating"
          + (f"; normal field lambda = {a.lam} (fairsurf only)" if not peer else ""))
    print(f"{'problem':<30}{'unknowns':>10}{'time s':>9}{'peak MB':>9}{'ratio':>8}{'max |dP|':>11}")
    with tempfile.TemporaryDirectory() as tmp:
        for c in (int(x) for x in a.counts.split(",")):
            path = os.path.join(tmp, "scene.json")
            with open(path, "w") as f:
                json.dump(scene(c, a.lam), f)
            out_path = os.path.join(tmp, "result.json")
            ours, theirs, our_mem, their_mem = [], [], [], []
            for _ in range(a.repeats):
                out, mb = peak_mb([a.binary, "solve", path, "-o", out_path, "--json"])
                r = json.loads(out)
                ours.append(r["timings_s"]["total"])
                our_mem.append(mb)
                if peer:
                    out, mb = peak_mb([sys.executable, "-c", PEER, path])
                    q = json.loads(out)
                    theirs.append(q["seconds"])
                    their_mem.append(mb)
            t_ours = statistics.median(ours)
            name = f"fairsurf {c}x{c}" + (" + field" if not peer else "")
            if peer:
                with open(out_path) as f:
                    net = json.load(f)["surface"]["control_points"]
                mine = [v for row in net for v in row]
                diff = max(max(abs(x - y) for x, y in zip(m, t)) for m, t in zip(mine, q["net"]))
                t_peer = statistics.median(theirs)
                print(f"{name:<30}{r['unknowns']:>10}{t_ours:>9.3f}{max(our_mem):>9.0f}"
                      f"{t_peer / t_ours:>8.2f}{diff:>11.1e}")
                print(f"{'scipy splu ' + str(c) + 'x' + str(c):<30}{q['unknowns']:>10}{t_peer:>9.3f}"
                      f"{max(their_mem):>9.0f}")
            else:
                print(f"{name:<30}{r['unknowns']:>10}{t_ours:>9.3f}{max(our_mem):>9.0f}")


if __name__ == "__main__":
    main()
