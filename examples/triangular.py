#!/usr/bin/env python3
"""Writes the triangular-surface example scenes of examples/ (Veltkamp & Wesselink):
python3 examples/triangular.py. Plain standard library; deterministic.

- vw_fig1_point_normal.json: a flat sheet, boundary fixed, pulled up at one point
  whose normal is prescribed (the paper's Fig. 1).
- vw_fig2_curve.json: the same sheet made to pass through a space curve; the patches
  it crosses are split so that patch edges interpolate it (Fig. 2, Fig. 3).
- vw_hexagon_hole.json / vw_pentagon_hole.json: an N-sided hole in a sphere filled by
  a fan of quartic patches with exact G1 inside (section 4.3).
- vw_fig5_directors.json, vw_fig6_attractors.json, vw_fig7_surface_attractor.json,
  vw_fig8_operators.json, vw_repellor.json: the flat sheet shaped by external energy
  operators (section 5): two directors, two point attractors, a surface attractor, a
  mix (director, plane, line and edge-to-curve attractors), and a point repellor.
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def grid(m):
    """The unit square as m x m squares, each cut along its diagonal (counter-clockwise)."""
    vid = lambda i, j: j * (m + 1) + i
    vertices = [[i / m, j / m, 0.0] for j in range(m + 1) for i in range(m + 1)]
    triangles = []
    for j in range(m):
        for i in range(m):
            a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
            triangles += [[a, b, c], [a, c, d]]
    return vertices, triangles


def write(name, scene):
    with open(os.path.join(HERE, name), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


def fig1():
    v, t = grid(4)
    # Triangle 18 is the lower half of square (1, 2); its centroid is (0.42, 0.58).
    at = {"triangle": 18, "bary": [1 / 3, 1 / 3, 1 / 3]}
    write("vw_fig1_point_normal.json", {
        "name": "Veltkamp & Wesselink Fig. 1: point and normal constraint",
        "description": "A flat square sheet of 32 quartic triangular patches, boundary fixed, "
                       "pulled up to z = 0.35 at one point where the normal is tilted towards +x; "
                       "stretch + bend with exact G1 across every interior edge.",
        "surface": {"type": "triangular", "degree": 4, "vertices": v, "triangles": t},
        "energy": {"stretch": 0.1, "bend": 1.0},
        "constraints": [
            {"type": "point", "name": "pull", "at": at, "target": [0.4167, 0.5833, 0.35]},
            {"type": "normal", "name": "tilt", "at": at, "normal": [0.5, 0.0, 1.0]},
        ],
    })


def fig2():
    v, t = grid(4)
    curve = [[0.15, 0.2, 0.0], [0.35, 0.75, 0.45], [0.65, 0.25, 0.45], [0.85, 0.8, 0.0]]
    write("vw_fig2_curve.json", {
        "name": "Veltkamp & Wesselink Fig. 2: curve interpolation",
        "description": "The flat sheet made to pass through a cubic space curve from one patch to a "
                       "non-adjacent one: the crossed patches are split (Fig. 3) and the chain of new "
                       "edges takes the curve's control points; quartic patches, G1 at the vertices.",
        "surface": {"type": "triangular", "degree": 4, "vertices": v, "triangles": t},
        "energy": {"stretch": 0.1, "bend": 1.0},
        "continuity": {"edges": "relaxed"},
        "constraints": [{
            "type": "curve", "name": "ridge", "control_points": curve,
            "from": {"triangle": 1, "bary": [0.4, 0.2, 0.4]},
            "to": {"triangle": 30, "bary": [0.3, 0.4, 0.3]},
        }],
    })


def hole(sides, name):
    """An N-sided hole in the sphere of radius 2 around (0, 0, -1): a fan of N quartic
    patches; the boundary control points are the flat ones lifted onto the sphere."""
    n = 4
    ring = [[math.cos(2 * math.pi * k / sides), math.sin(2 * math.pi * k / sides)] for k in range(sides)]
    vertices = [[0.0, 0.0, 1.0]] + [[x, y, 0.0] for x, y in ring]
    triangles = [[0, 1 + k, 1 + (k + 1) % sides] for k in range(sides)]
    lift = lambda x, y: math.sqrt(4.0 - x * x - y * y) - 1.0
    for p in vertices:
        p[2] = lift(p[0], p[1])
    # Control points: vertices, then n-1 per edge (sorted vertex pairs, from the smaller),
    # then the interiors; the flat ones lifted onto the sphere (so the boundary lies on it).
    edges = sorted({tuple(sorted((t[a], t[b]))) for t in triangles for a, b in ((0, 1), (1, 2), (2, 0))})
    points = [list(p) for p in vertices]
    for a, b in edges:
        for r in range(1, n):
            x = vertices[a][0] + r / n * (vertices[b][0] - vertices[a][0])
            y = vertices[a][1] + r / n * (vertices[b][1] - vertices[a][1])
            points.append([x, y, lift(x, y)])
    for a, b, c in triangles:
        for k in range(1, n - 1):
            for j in range(1, n - k):
                i = n - j - k
                x = (i * vertices[a][0] + j * vertices[b][0] + k * vertices[c][0]) / n
                y = (i * vertices[a][1] + j * vertices[b][1] + k * vertices[c][1]) / n
                points.append([x, y, 0.0])
    write(name, {
        "name": f"A {sides}-sided hole filled with G1 inside",
        "description": f"A fan of {sides} quartic triangular patches fills an {sides}-sided hole in a "
                       "sphere (radius 2); the boundary is fixed on the sphere, the inside starts flat. "
                       "Bend energy, exact G1 at the centre vertex and across the inner edges.",
        "surface": {"type": "triangular", "degree": n, "vertices": vertices, "triangles": triangles,
                    "control_points": points},
        "energy": {"bend": 1.0},
    })


def sheet(name, title, description, operators, edges="exact"):
    v, t = grid(4)
    write(name, {
        "name": title,
        "description": description,
        "surface": {"type": "triangular", "degree": 4, "vertices": v, "triangles": t},
        "energy": {"stretch": 0.1, "bend": 1.0},
        "continuity": {"edges": edges},
        "operators": operators,
    })


def operators():
    sheet("vw_fig5_directors.json", "Veltkamp & Wesselink Fig. 5: two directors",
          "The flat sheet (32 quartic patches, boundary fixed, exact G1) with two director "
          "operators over triangular regions of the domain, turning the normals there towards "
          "their directions.",
          [{"type": "director", "name": "left", "strength": 20.0, "direction": [0.8, 0.0, 1.0],
            "domain_region": [[0.2, 0.2], [0.45, 0.25], [0.3, 0.5]]},
           {"type": "director", "name": "right", "strength": 20.0, "direction": [-0.6, -0.6, 1.0],
            "domain_region": [[0.55, 0.55], [0.85, 0.6], [0.65, 0.85]]}])
    sheet("vw_fig6_attractors.json", "Veltkamp & Wesselink Fig. 6: two point attractors",
          "The flat sheet pulled up at one surface point and down over a region by two point "
          "attractors; the bend energy keeps both from reaching their points.",
          [{"type": "point_attractor", "name": "up", "strength": 200.0, "point": [0.3, 0.3, 0.5],
            "at": {"triangle": 10, "bary": [1 / 3, 1 / 3, 1 / 3]}},
           {"type": "point_attractor", "name": "down", "strength": 50.0, "point": [0.7, 0.7, -0.4],
            "domain_region": [[0.6, 0.6], [0.8, 0.6], [0.8, 0.8], [0.6, 0.8]]}])
    # Triangle 18: the lower half of square (1, 2): corners (0.25,0.5), (0.5,0.5), (0.5,0.75).
    sheet("vw_fig7_surface_attractor.json", "Veltkamp & Wesselink Fig. 7: a surface attractor",
          "A triangular region of one patch pulled towards a tilted flat triangle above it, "
          "corner to corner.",
          [{"type": "surface_attractor", "name": "lift", "strength": 500.0,
            "region": [{"triangle": 18, "polygon": [[0.9, 0.05], [0.05, 0.9], [0.05, 0.05]]}],
            "surface": {"degree": 1, "control_points": [[0.27, 0.51, 0.15], [0.49, 0.51, 0.25],
                                                        [0.49, 0.73, 0.4]]}}])
    sheet("vw_fig8_operators.json", "Veltkamp & Wesselink Fig. 8: a surface shaped by operators",
          "A director, a plane attractor, a line attractor and an interior mesh edge pulled "
          "towards a curve, together on the flat sheet (relaxed G1).",
          [{"type": "director", "name": "tilt", "strength": 10.0, "direction": [0.0, 0.7, 1.0],
            "domain_region": [[0.15, 0.6], [0.4, 0.6], [0.4, 0.85], [0.15, 0.85]]},
           {"type": "plane_attractor", "name": "shelf", "strength": 100.0, "normal": [0.0, 0.0, 1.0],
            "offset": 0.25, "domain_region": [[0.55, 0.15], [0.85, 0.15], [0.85, 0.4], [0.55, 0.4]]},
           {"type": "line_attractor", "name": "rail", "strength": 100.0, "point": [0.0, 0.5, 0.3],
            "direction": [1.0, 0.0, 0.0], "at": {"triangle": 20, "bary": [1 / 3, 1 / 3, 1 / 3]}},
           {"type": "curve_attractor", "name": "crease", "strength": 100.0, "edge": [6, 12],
            "control_points": [[0.25, 0.25, 0.0], [0.375, 0.375, -0.3], [0.5, 0.5, 0.0]]}],
          edges="relaxed")
    sheet("vw_repellor.json", "A point repellor",
          "The flat sheet pushed away from a point just above its centre by a repellor "
          "1/|S - P|^2 (eq. 23): solved by Newton's method from the quadratic solution.",
          [{"type": "repellor", "name": "away", "strength": 0.05, "point": [0.5, 0.5, 0.05],
            "at": {"triangle": 20, "bary": [0.2, 0.4, 0.4]}}])


fig1()
fig2()
operators()
hole(6, "vw_hexagon_hole.json")
hole(5, "vw_pentagon_hole.json")
