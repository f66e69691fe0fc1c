"""A tour of the fairsurf module, notebook style: run it cell by cell or whole.

    python python/examples/tour.py [OUTPUT_DIR]

It builds a scene in numpy, solves it, reads the report, samples the surface,
meshes and exports it, draws it, and sweeps a weight over threads. CI runs it.
"""

# %% A scene from numpy: a bi-quintic patch over a wavy boundary, the
# interior free (NaN points are free, as null is in a scene file).
import sys
import tempfile
from pathlib import Path

import numpy as np

import fairsurf

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="fairsurf-tour-"))
out.mkdir(parents=True, exist_ok=True)

n = 5
u, v = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), indexing="ij")
net = np.stack([u, v, 0.2 * np.sin(3 * u) * np.cos(2 * v)], axis=-1)
net[1:-1, 1:-1] = np.nan

# fairsurf.Problem builds the scene (a dict: print(scene.to_json()) shows it);
# a plain dict in the scene format works everywhere too.
scene = fairsurf.Problem(net).bend(1)

# %% Solve. The report says how good the answer is, checked on the net as written.
r = fairsurf.solve(scene)
rep = r.report
print(r)
print(f"energy {rep['energy']:.10g}, gradient {rep['gradient_norm']:.1e}, "
      f"checked excess {rep['check']['excess']:.1e} (tolerance {rep['check']['tolerance']:.0e})")
print("control points", r.control_points.shape, r.control_points.dtype)

# %% Sample the surface: points, normals and curvatures on a grid (numpy broadcasting).
s = np.linspace(0, 1, 41)
c = r.curvatures(s[:, None], s[None, :])
print(f"mean curvature on a 41×41 grid: |H| max {np.nanmax(np.abs(c.mean)):.4f}")
print(f"thin-plate integrand κ₁²+κ₂² mean {np.nanmean(c.k1**2 + c.k2**2):.4f}")

# %% Mesh, export, picture.
mesh = r.mesh(32)
print("mesh", mesh.vertices.shape, mesh.faces.shape)
print(r.export(out / "tour.step"))
print(r.export(out / "tour.ply", resolution=32))
png = r.render(out / "tour.png", width=600, height=450, zebra=16)
print(f"{out / 'tour.png'}: {len(png)} bytes")

# %% A sweep: Wu & Yang's stretch with a normal field of growing weight λ,
# solved on two threads. Larger λ lowers the field term per unit weight
# (here a field that leans toward +x along u) at the cost of more stretch. (A constant field would change nothing:
# with N = (0, 0, 1) the term is λ times the Dirichlet energy of z alone, and
# the stretch minimizer's z is already harmonic.)
# Each Problem step returns a new Problem, so one base serves the sweep.
field = np.array([[[0.0, 0.0, 1.0]], [[0.6, 0.0, 1.0]]])
base = fairsurf.Problem(net).stretch(1)
sweep = [base] + [base.normal_field(lam, field) for lam in [1, 10, 100]]
for lam, res in zip([0, 1, 10, 100], fairsurf.solve_many(sweep, threads=2)):
    terms = res.report["terms"]
    misfit = terms["normal_field"] / lam if lam else float("nan")
    print(f"λ = {lam:>3}: energy {res.report['energy']:.6g}, stretch {terms['stretch']:.6g}, "
          f"field term / λ {misfit:.6g}")

# %% Errors name the JSON path.
bad = scene.bend(-1)
try:
    fairsurf.solve(bad)
except fairsurf.SceneError as e:
    print(f"SceneError at {e.path!r}: {e}")
