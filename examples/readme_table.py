#!/usr/bin/env python3
"""Prints the README's examples table: solves every examples/*.json with the built
`fairsurf` binary (target/debug or target/release, as given) and tabulates its report."""
import glob
import json
import os
import subprocess
import sys

binary = sys.argv[1] if len(sys.argv) > 1 else "target/debug/fairsurf"
rows = ["| scene | method | degree | free | energy | area | D | B | mean \\|H\\| | normals vs N (mean / max) | accuracy | cond. | time |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
for path in sorted(glob.glob(os.path.join(os.path.dirname(__file__), "*.json"))):
    scene = json.load(open(path))
    rep = json.loads(subprocess.run([binary, "solve", "--json", path], check=True, capture_output=True, text=True).stdout)
    n, m = scene["surface"]["degree"]
    dev = rep.get("normal_deviation_deg")
    devs = f"{dev['mean']:.2f}° / {dev['max']:.2f}°" if dev else "–"
    method = scene.get("method", "minimize")
    if method == "minimize":
        energy = f"{rep['energy']:.6g}"
        accuracy = f"grad {rep['relative_gradient']:.1e}"
    else:
        energy = "–"
        accuracy = f"eq. {rep['residual']:.1e}"
    cond = rep.get("condition_estimate")
    conds = f"{cond:.1e}" if cond is not None else "–"
    rows.append(
        f"| `{os.path.basename(path)}` | {method} | {n}×{m} | {rep['free_points']} | {energy} | {rep['area']:.6f} | "
        f"{rep['dirichlet']:.6f} | {rep['biharmonic']:.5g} | {rep['abs_mean_curvature']['mean']:.4f} | {devs} | {accuracy} | "
        f"{conds} | {rep['timings_s']['total'] * 1000:.1f} ms |")
print("\n".join(rows))
