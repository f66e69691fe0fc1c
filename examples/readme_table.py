#!/usr/bin/env python3
"""Prints the README's examples table: solves every examples/*.json with the built
`fairsurf` binary (target/debug or target/release, as given) and tabulates its report."""
import glob
import json
import os
import subprocess
import sys

binary = sys.argv[1] if len(sys.argv) > 1 else "target/debug/fairsurf"
rows = ["| scene | degree | free | energy | area | D | B | normals vs N (mean / max) | rel. gradient | cond. | time |",
        "|---|---|---|---|---|---|---|---|---|---|---|"]
for path in sorted(glob.glob(os.path.join(os.path.dirname(__file__), "*.json"))):
    scene = json.load(open(path))
    rep = json.loads(subprocess.run([binary, "solve", "--json", path], check=True, capture_output=True, text=True).stdout)
    n, m = scene["surface"]["degree"]
    dev = rep.get("normal_deviation_deg")
    devs = f"{dev['mean']:.2f}° / {dev['max']:.2f}°" if dev else "–"
    rows.append(
        f"| `{os.path.basename(path)}` | {n}×{m} | {rep['free_points']} | {rep['energy']:.6g} | {rep['area']:.6f} | "
        f"{rep['dirichlet']:.6f} | {rep['biharmonic']:.5g} | {devs} | {rep['relative_gradient']:.1e} | "
        f"{rep['condition_estimate']:.1e} | {rep['timings_s']['total'] * 1000:.1f} ms |")
print("\n".join(rows))
