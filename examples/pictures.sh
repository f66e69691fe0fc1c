#!/usr/bin/env bash
# Regenerates every picture in examples/pictures/ (the README shows them):
#   bash examples/pictures.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build -q -p fairsurf-cli
f=target/debug/fairsurf
out=examples/pictures
mkdir -p "$out"
r() { "$f" render "$@" | head -1; }

# Wu & Yang 2015: the effect of λ (normal field) and γ (initial surface).
r examples/wu_yang_fig1_l10_g0.json examples/wu_yang_fig1_l10_g100.json \
  examples/wu_yang_fig1_l10_g200.json examples/wu_yang_fig1_l50_g0.json \
  -o "$out/wu_yang_fig1.png" --size 1600x440
r examples/wu_yang_fig2_dirichlet.json examples/wu_yang_fig2_l1.json \
  examples/wu_yang_fig2_l10.json examples/wu_yang_fig2_l50.json \
  -o "$out/wu_yang_fig2.png" --size 1600x440
r examples/wu_yang_fig4_l0.json examples/wu_yang_fig4_l500.json \
  -o "$out/wu_yang_fig4_normals.png" --size 1200x520 --normals --net
r examples/wu_yang_fig5_l5.json examples/wu_yang_fig5_l500.json examples/wu_yang_fig5_thin_plate.json \
  -o "$out/wu_yang_fig5_zebra.png" --size 1500x480 --colour none --zebra 24

# Wu & Yang Fig. 4 on a bicubic B-spline: thin plate, Bézier field, sampled normals.
r examples/bspline_hole.json examples/bspline_hole_guided.json examples/bspline_hole_sampled.json \
  -o "$out/bspline_holes.png" --size 1500x480 --colour none --zebra 24

# Wu & Yang Fig. 1-5 on bicubic B-splines (16 x 16 and 20 x 20 control points).
r examples/bspline_wu_yang_fig1_l10_g0.json examples/bspline_wu_yang_fig1_l10_g100.json \
  examples/bspline_wu_yang_fig2_l10.json examples/bspline_wu_yang_fig3_l50.json \
  -o "$out/bspline_wu_yang_fig1_3.png" --size 1600x440 --range 0,4
r examples/bspline_wu_yang_fig4_l0.json examples/bspline_wu_yang_fig4_l500.json \
  examples/bspline_wu_yang_fig5_thin_plate.json examples/bspline_wu_yang_fig5_l500.json \
  -o "$out/bspline_wu_yang_fig4_5.png" --size 1600x440 --colour none --zebra 24

# Monterde & Ugail 2004: the four surfaces of Table 1 with |H| on [0, 1] (their Fig. 8–9).
r --compare examples/monterde_ugail_model.json -o "$out/monterde_ugail_table1.png" \
  --range 0,1 --size 1600x460
r --compare examples/monterde_ugail_catenoid.json -o "$out/monterde_ugail_catenoid.png" \
  --range 0,1 --size 1600x460
r examples/monterde_ugail_fig7.json examples/monterde_ugail_fig7_harmonic_mask.json \
  -o "$out/monterde_ugail_fig7.png" --size 1200x520 --net --range 0,1
r examples/biharmonic_mask_bump.json -o "$out/biharmonic_mask_bump.png" \
  --size 900x620 --colour mean --net
r examples/quickstart.json -o "$out/quickstart.png" --size 900x620 --net

# Veltkamp & Wesselink: triangular surfaces, drawn over their own triangles.
r examples/vw_fig1_point_normal.json examples/vw_fig2_curve.json \
  -o "$out/vw_fig1_fig2.png" --size 1200x520 --net --resolution 24 --range 0,15
r examples/vw_hexagon_hole.json examples/vw_pentagon_hole.json \
  -o "$out/vw_holes_zebra.png" --size 1200x520 --colour none --zebra 24 --resolution 32
r examples/vw_fig5_directors.json examples/vw_fig6_attractors.json \
  examples/vw_fig7_surface_attractor.json examples/vw_fig8_operators.json examples/vw_repellor.json \
  -o "$out/vw_operators.png" --size 1600x420 --resolution 24 --colour none --zebra 20
