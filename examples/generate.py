#!/usr/bin/env python3
"""Writes the example scenes of examples/ (run from anywhere: python3 examples/generate.py).

They rebuild the setups of Wu & Yang 2015, section 5. The paper does not print its
control points, so each scene constructs data of the same kind: degree, fixed rings,
kind of normal field (continuous Bezier or sampled), and the lambda/gamma values of
the figures. Plain standard library; output is deterministic.
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def binom(n, k):
    return math.comb(n, k)


def bern(n, t):
    return [binom(n, i) * t**i * (1 - t) ** (n - i) for i in range(n + 1)]


def dbern(n, t):
    if n == 0:
        return [0.0]
    low = bern(n - 1, t)
    return [n * ((low[i - 1] if i > 0 else 0.0) - (low[i] if i < n else 0.0)) for i in range(n + 1)]


def patch_eval(net, u, v, du=False, dv=False):
    n, m = len(net) - 1, len(net[0]) - 1
    bu = dbern(n, u) if du else bern(n, u)
    bv = dbern(m, v) if dv else bern(m, v)
    return [sum(bu[i] * bv[j] * net[i][j][c] for i in range(n + 1) for j in range(m + 1)) for c in range(3)]


def unit(a):
    l = math.sqrt(sum(x * x for x in a))
    return [x / l for x in a]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def patch_normal(net, u, v):
    return unit(cross(patch_eval(net, u, v, du=True), patch_eval(net, u, v, dv=True)))


def graph_net(n, m, f, sx=1.0, sy=1.0):
    """Control net with x, y on a uniform grid and z = f at the Greville points."""
    return [[[sx * i / n, sy * j / m, f(i / n, j / m)] for j in range(m + 1)] for i in range(n + 1)]


def r(x):
    return round(x, 12)


def clean(net):
    return [[None if p is None else [r(c) for c in p] for p in row] for row in net]


def sampled_normals(net, np_, mp, override=None):
    out = []
    for i in range(np_ + 1):
        row = []
        for j in range(mp + 1):
            u, v = i / np_, j / mp
            nrm = override(u, v) if override else None
            row.append([r(c) for c in (nrm or patch_normal(net, u, v))])
        out.append(row)
    return out


def write(name, scene):
    with open(os.path.join(HERE, name), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


def fig1():
    # A degree-5x5 dome-saddle; the field asks for the normals of a ridge running along v.
    n = 5
    init = graph_net(n, n, lambda x, y: 0.25 * math.sin(math.pi * x) * math.sin(math.pi * y))
    ridge = lambda x, y: 0.5 * math.exp(-12 * (x - 0.5) ** 2) * math.sin(math.pi * y)
    target = graph_net(n, n, ridge)
    field = [[[r(c) for c in patch_normal(target, i / n, j / n)] for j in range(n + 1)] for i in range(n + 1)]
    for lam, gam in [(10, 0), (50, 0), (10, 100), (10, 200)]:
        energy = {"stretch": 1, "normal_field": {"weight": lam, "degree": [n, n], "control_points": field}}
        if gam:
            energy["guide_surface"] = {"weight": gam}
        write(f"wu_yang_fig1_l{lam}_g{gam}.json", {
            "name": f"Wu & Yang Fig. 1: extended membrane, lambda = {lam}, gamma = {gam}",
            "description": "Degree 5x5, boundary fixed; a degree-5x5 Bezier normal field of a ridge; "
                           "the guide surface (when gamma > 0) is the initial dome.",
            "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(init)},
            "fixed_rings": 1,
            "energy": energy,
        })


def hat(x, y):
    # A hat whose brim waves along the boundary.
    d = math.hypot(x - 0.5, y - 0.5)
    return 0.45 * math.exp(-10 * d * d) + 0.06 * math.sin(4 * math.pi * x) * math.sin(4 * math.pi * y) * (1 - math.exp(-20 * d * d))


def fig2_3():
    n, g = 8, 32
    init = graph_net(n, n, hat)
    def flat_top(u, v):
        return [0.0, 0.0, 1.0] if math.hypot(u - 0.5, v - 0.5) < 0.22 else None
    normals2 = sampled_normals(init, g, g, flat_top)
    write("wu_yang_fig2_dirichlet.json", {
        "name": "Wu & Yang Fig. 2(c): Dirichlet extremal of the hat's boundary",
        "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(init)},
        "fixed_rings": 1,
        "energy": {"stretch": 1},
    })
    for lam in [1, 10, 50]:
        write(f"wu_yang_fig2_l{lam}.json", {
            "name": f"Wu & Yang Fig. 2: sampled extended membrane, lambda = {lam}, gamma = 0",
            "description": "8x8 hat with a wavy brim; 33x33 sampled unit normals: vertical on the top "
                           "(flatten it), the initial surface's elsewhere.",
            "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(init)},
            "fixed_rings": 1,
            "energy": {"stretch": 1, "normal_field": {"weight": lam},
                       "sampling": {"grid": [g, g], "normal_samples": normals2}},
        })
    # Fig. 3: same hat, normals of a sharper, taller cone; weights only near the apex.
    cone = graph_net(n, n, lambda x, y: 0.7 * max(0.0, 1 - 2.2 * math.hypot(x - 0.5, y - 0.5)))
    normals3 = sampled_normals(cone, g, g)
    weights = [[r(1.0 + 4.0 * math.exp(-20 * ((i / g - 0.5) ** 2 + (j / g - 0.5) ** 2))) for j in range(g + 1)] for i in range(g + 1)]
    for lam in [10, 50]:
        write(f"wu_yang_fig3_l{lam}.json", {
            "name": f"Wu & Yang Fig. 3: sampled extended membrane toward a cone, lambda = {lam}",
            "description": "Same hat; sampled normals of a cone, per-sample weights raised near the apex.",
            "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(init)},
            "fixed_rings": 1,
            "energy": {"stretch": 1, "normal_field": {"weight": lam},
                       "sampling": {"grid": [g, g], "normal_samples": normals3, "normal_weights": weights}},
        })


def fig4():
    # Hole filling: the ground truth has a salient crease-like ridge; its outer two rings
    # give G1 data; the interior starts flat (bilinear) and the normals come from the truth.
    n, g = 7, 28
    truth_f = lambda x, y: 0.5 * math.exp(-30 * (x - y) ** 2) * math.sin(math.pi * x) * math.sin(math.pi * y) + 0.15 * x
    truth = graph_net(n, n, truth_f)
    init = [[list(p) for p in row] for row in truth]
    for i in range(2, n - 1):
        for j in range(2, n - 1):
            init[i][j][2] = 0.15 * i / n  # the plane z = 0.15 x: the feature is lost
    normals = sampled_normals(truth, g, g)
    for lam in [0, 500]:
        energy = {"bend": 1, "sampling": {"grid": [g, g]}}
        if lam:
            energy["normal_field"] = {"weight": lam}
            energy["sampling"]["normal_samples"] = normals
        write(f"wu_yang_fig4_l{lam}.json", {
            "name": f"Wu & Yang Fig. 4: 7x7 hole filling, thin plate, lambda = {lam}",
            "description": "Two outer rings fixed from a ground-truth surface with a diagonal ridge (G1 to the "
                           "surroundings); sampled normals of the ground truth guide the filling.",
            "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(init)},
            "fixed_rings": 2,
            "energy": energy,
        })
    os.makedirs(os.path.join(HERE, "data"), exist_ok=True)
    write("data/wu_yang_fig4_ground_truth.json", {
        "name": "Wu & Yang Fig. 4(d): the ground truth of the hole-filling examples",
        "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(truth)},
        "free_points": [],
        "energy": {"bend": 1},
    })


def fig5():
    # Bi-quintic transition between a floor (z = 0, small u) and a raised shelf (large u)
    # with a sharp-ish shoulder in the truth; rings 0-1 and 4-5 come from the two sides.
    n, g = 5, 25
    step = lambda x, y: 0.5 / (1 + math.exp(-14 * (x - 0.5 - 0.12 * math.sin(2 * math.pi * y))))
    truth = graph_net(n, n, step)
    init = [[list(p) for p in row] for row in truth]
    for i in range(2, 4):
        for j in range(2, 4):
            init[i][j][2] = 0.5 * i / n
    normals = sampled_normals(truth, g, g)
    for lam in [5, 500]:
        write(f"wu_yang_fig5_l{lam}.json", {
            "name": f"Wu & Yang Fig. 5: bi-quintic transition surface, lambda = {lam}",
            "description": "Outer two rings fixed (G1 to the surfaces it joins); sampled normals of a "
                           "wavy step guide the blend.",
            "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(init)},
            "fixed_rings": 2,
            "energy": {"bend": 1, "normal_field": {"weight": lam},
                       "sampling": {"grid": [g, g], "normal_samples": normals}},
        })
    write("wu_yang_fig5_thin_plate.json", {
        "name": "Wu & Yang Fig. 5(b): the same transition by the plain thin-plate energy",
        "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(init)},
        "fixed_rings": 2,
        "energy": {"bend": 1},
    })


def quickstart():
    write("quickstart.json", {
        "name": "Quick start: a 4x4 membrane with a free interior",
        "description": "Boundary of a saddle; the four inner points are null (free, no initial value).",
        "surface": {"type": "tensor", "degree": [3, 3], "control_points": [
            [[0, 0, 0], [0, 1, 0.3], [0, 2, 0.3], [0, 3, 0]],
            [[1, 0, -0.3], None, None, [1, 3, -0.3]],
            [[2, 0, -0.3], None, None, [2, 3, -0.3]],
            [[3, 0, 0], [3, 1, 0.3], [3, 2, 0.3], [3, 3, 0]]]},
        "energy": {"stretch": 1, "normal_field": {"weight": 5, "degree": [0, 0], "control_points": [[[0, 0, 1]]]}},
    })


# Monterde & Ugail 2004. The degree-5 semicircle polygon of section 2.1, as printed.
SEMICIRCLE5 = [[-1.0, 0.0], [-1.0, 0.72], [-0.515308, 1.25143], [0.515308, 1.25143], [1.0, 0.72], [1.0, 0.0]]


def solve_linear(a, b):
    """Gaussian elimination with partial pivoting (small dense systems)."""
    n = len(a)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda k: abs(m[k][c]))
        m[c], m[p] = m[p], m[c]
        for k in range(c + 1, n):
            f = m[k][c] / m[c][c]
            for j in range(c, n + 1):
                m[k][j] -= f * m[c][j]
    x = [0.0] * n
    for c in reversed(range(n)):
        x[c] = (m[c][n] - sum(m[c][j] * x[j] for j in range(c + 1, n))) / m[c][c]
    return x


def interpolate5(f):
    """Degree-5 Bezier curve through f(k/5), k = 0..5 (f returns a list of coordinates)."""
    a = [bern(5, k / 5) for k in range(6)]
    vals = [f(k / 5) for k in range(6)]
    cols = [solve_linear(a, [v[c] for v in vals]) for c in range(len(vals[0]))]
    return [[cols[c][i] for c in range(len(cols))] for i in range(6)]


def ring_net(n, m, rows0, rowsn, cols0, colsm):
    """A net with the given boundary (row i=0, row i=n, column j=0, column j=m), inner points null."""
    net = [[None] * (m + 1) for _ in range(n + 1)]
    for j in range(m + 1):
        net[0][j], net[n][j] = rows0[j], rowsn[j]
    for i in range(n + 1):
        net[i][0], net[i][m] = cols0[i], colsm[i]
    return net


def monterde_ugail():
    s = SEMICIRCLE5
    # Model problem (section 2.1, Table 1): semicircles of radius 1 (z = 0) and 0.5 (z = 1),
    # joined by straight side curves. This placement reproduces Table 1 to the printed digits.
    model = [[[s[j][0] * (1 - 0.5 * i / 5), s[j][1] * (1 - 0.5 * i / 5), i / 5] for j in range(6)] for i in range(6)]
    model = ring_net(5, 5, model[0], model[5], [row[0] for row in model], [row[5] for row in model])
    cite = "Monterde & Ugail 2004"
    write("monterde_ugail_model_harmonic.json", {
        "name": f"{cite}, Fig. 1: the harmonic Bezier surface of the model problem",
        "description": "Determined by the first and last rows (the two semicircles) alone (Prop. 1).",
        "surface": {"type": "tensor", "degree": [5, 5], "control_points": clean(model)},
        "method": "harmonic",
    })
    write("monterde_ugail_model.json", {
        "name": f"{cite}, Fig. 2 / Table 1: the biharmonic Bezier surface of the model problem",
        "description": "Semicircles of radius 1 and 0.5 (the printed degree-5 polygon) one unit apart, "
                       "straight side curves. `fairsurf compare` prints Table 1.",
        "surface": {"type": "tensor", "degree": [5, 5], "control_points": clean(model)},
        "method": "biharmonic",
    })
    # Catenoid (section 4.3.2, Table 2): (cosh v cos u, cosh v sin u, v), u in [0, pi], v in [0, arccosh 2].
    # Edge curves: the printed polygon scaled to radius 1 and 2; side curves: the catenary
    # (cosh v, v) interpolated at six equally spaced parameters (Table 2 to about 5 digits).
    a = math.acosh(2.0)
    side = interpolate5(lambda t: [math.cosh(a * t), a * t])
    cat = ring_net(
        5, 5,
        [[p[0], p[1], 0.0] for p in s],
        [[2 * p[0], 2 * p[1], a] for p in s],
        [[-q[0], 0.0, q[1]] for q in side],
        [[q[0], 0.0, q[1]] for q in side],
    )
    write("monterde_ugail_catenoid.json", {
        "name": f"{cite}, Fig. 4 / Table 2: biharmonic surface with the boundary of a catenoid",
        "description": "Degree-5 approximations of the boundary of (cosh v cos u, cosh v sin u, v) "
                       "(the paper misprints the second coordinate), whose exact area is 7.51007.",
        "surface": {"type": "tensor", "degree": [5, 5], "control_points": clean(cat)},
        "method": "biharmonic",
    })
    # Fig. 7 / Table 4: four semicircles of radius 1 standing on the sides of a 2x2 square
    # (they lie on a sphere of radius sqrt 2). Reproduces Table 4 to the printed digits.
    def arc(k, along):
        p = s[k]
        return along(1 + p[0], p[1])
    fig7 = ring_net(
        5, 5,
        [arc(j, lambda x, z: [x, 0.0, z]) for j in range(6)],
        [arc(j, lambda x, z: [x, 2.0, z]) for j in range(6)],
        [arc(i, lambda y, z: [0.0, y, z]) for i in range(6)],
        [arc(i, lambda y, z: [2.0, y, z]) for i in range(6)],
    )
    write("monterde_ugail_fig7.json", {
        "name": f"{cite}, Fig. 7 / Table 4: four semicircles on a sphere, biharmonic surface",
        "surface": {"type": "tensor", "degree": [5, 5], "control_points": clean(fig7)},
        "method": "biharmonic",
    })
    write("monterde_ugail_fig7_harmonic_mask.json", {
        "name": f"{cite}, Table 4: the same boundary filled by the harmonic mask",
        "surface": {"type": "tensor", "degree": [5, 5], "control_points": clean(fig7)},
        "method": "harmonic_mask",
    })
    # The biharmonic mask needs two rings: a 7x7 net whose two outer rings sample z = sin(pi u) sin(pi v).
    n = 7
    bump = [[[i / n, j / n, r(math.sin(math.pi * i / n) * math.sin(math.pi * j / n)) if min(i, j, n - i, n - j) <= 1 else None]
             for j in range(n + 1)] for i in range(n + 1)]
    bump = [[p if p[2] is not None else None for p in row] for row in bump]
    write("biharmonic_mask_bump.json", {
        "name": f"{cite}, eq. (7): the biharmonic mask fills a 7x7 net from its two outer rings",
        "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(bump)},
        "method": "biharmonic_mask",
    })


# Veltkamp & Wesselink's four constraint kinds (section 4.1) at points of the unit square.
FOUR_CONSTRAINTS = [
    {"type": "point", "name": "peak", "at": {"uv": [0.35, 0.4]}, "target": [0.35, 0.4, 0.3]},
    {"type": "normal", "name": "slope", "at": {"uv": [0.35, 0.4]}, "normal": [-0.4, 0.2, 1.0]},
    {"type": "in_plane", "name": "shelf", "at": {"uv": [0.7, 0.7]}, "normal": [0, 0, 1], "offset": -0.1},
    {"type": "on_line", "name": "post", "at": {"uv": [0.75, 0.25]},
     "point": [0.8, 0.2, 0.0], "direction": [0, 0, 1]},
]


def tensor_operators():
    """Veltkamp & Wesselink's operators (section 5) on a tensor-product patch."""
    n = 6
    # A flat unit square as the boundary ring; the interior is shaped by operators.
    frame = [[[r(i / n), r(j / n), 0.0] for j in range(n + 1)] for i in range(n + 1)]
    cite = "Veltkamp & Wesselink section 5 on a tensor patch"
    write("tensor_operators.json", {
        "name": f"{cite}: two point attractors, a director over a region and a plane attractor",
        "description": "Degree 6x6, boundary fixed on the unit square, thin plate with a little membrane.",
        "surface": {"type": "tensor", "degree": [n, n], "control_points": frame},
        "fixed_rings": 1,
        "energy": {"stretch": 0.1, "bend": 1},
        "operators": [
            {"type": "point_attractor", "name": "peak", "strength": 500, "at": [0.3, 0.3], "point": [0.3, 0.3, 0.35]},
            {"type": "point_attractor", "name": "dip", "strength": 500, "at": [0.7, 0.35], "point": [0.7, 0.35, -0.2]},
            {"type": "director", "name": "tilt", "strength": 20,
             "region": [[0.45, 0.6], [0.85, 0.6], [0.85, 0.9], [0.45, 0.9]], "direction": [0.4, 0.0, 1.0]},
            {"type": "plane_attractor", "name": "shelf", "strength": 100,
             "region": [[0.1, 0.6], [0.35, 0.6], [0.35, 0.9], [0.1, 0.9]], "normal": [0, 0, 1], "offset": 0.15},
        ],
    })
    write("tensor_repellor.json", {
        "name": f"{cite}: a repellor pushes the surface away from a point under it (eq. 23, Newton's method)",
        "surface": {"type": "tensor", "degree": [n, n], "control_points": frame},
        "fixed_rings": 1,
        "energy": {"bend": 1},
        "operators": [
            {"type": "repellor", "name": "push", "strength": 0.05, "at": [0.5, 0.5], "point": [0.5, 0.5, -0.1]},
        ],
    })
    write("tensor_constraints.json", {
        "name": f"Veltkamp & Wesselink's constraints (section 4.1) on a tensor patch: a point, a normal, a plane and a line",
        "description": "Degree 7x7, boundary fixed on the unit square, thin plate with a little membrane. "
                       "The surface passes through a point with a prescribed normal there, touches a plane "
                       "and meets a vertical line, each exactly.",
        "surface": {"type": "tensor", "degree": [7, 7],
                    "control_points": [[[r(i / 7), r(j / 7), 0.0] for j in range(8)] for i in range(8)]},
        "fixed_rings": 1,
        "energy": {"stretch": 0.1, "bend": 1},
        "constraints": FOUR_CONSTRAINTS,
    })


def editor_degree10():
    """The editor's drag scene: degree 10, lambda > 0, the initial net as guide."""
    n = 10
    wave = lambda x, y: 0.15 * math.sin(2 * math.pi * x) * math.cos(math.pi * y) + 0.1 * x * y
    field = [[[r(0.3 * (i / 3 - 0.5)), r(-0.2 * (j / 3 - 0.5)), 1.0] for j in range(4)] for i in range(4)]
    write("editor_degree10.json", {
        "name": "Degree 10 with a normal field (lambda = 10) and the initial net as guide (gamma = 1)",
        "description": "Wu & Yang's E1 at degree 10: drag the boundary in the editor; each drag re-solves "
                       "with the kept factorization (only the right-hand side changes).",
        "surface": {"type": "tensor", "degree": [n, n], "control_points": clean(graph_net(n, n, wave))},
        "fixed_rings": 1,
        "energy": {
            "stretch": 1,
            "normal_field": {"weight": 10, "degree": [3, 3], "control_points": field},
            "guide_surface": {"weight": 1},
        },
    })


def bspline_hole():
    """A bicubic B-spline of 14 x 14 control points over uneven knots: two rings
    of a wavy sheet kept, the 10 x 10 inside free (null), the thin plate."""
    p, c = 3, 14
    inner = [0.08, 0.16, 0.25, 0.33, 0.42, 0.5, 0.58, 0.67, 0.75, 0.84, 0.92]
    knots = [0.0] * (p + 1) + inner[: c - p - 1] + [1.0] * (p + 1)
    # Greville abscissae place the net over the sheet.
    grev = [sum(knots[i + 1:i + p + 1]) / p for i in range(c)]
    wave = lambda x, y: 0.2 * math.sin(2.5 * math.pi * x) * math.cos(1.5 * math.pi * y) + 0.3 * x * y
    net = [[[r(2 * grev[i]), r(2 * grev[j]), r(wave(grev[i], grev[j]))]
            if min(i, j, c - 1 - i, c - 1 - j) < 2 else None
            for j in range(c)] for i in range(c)]
    write("bspline_hole.json", {
        "name": "Bicubic B-spline hole, 14 x 14 control points, thin plate",
        "description": "Two rings of a wavy sheet fixed (position and tangent plane along the "
                       "boundary), the 100 inner control points free: Wu & Yang's E2 over "
                       "11 x 11 knot spans.",
        "surface": {"type": "bspline", "degree": [p, p], "knots": [knots, knots],
                    "control_points": net},
        "fixed_rings": 2,
        "energy": {"bend": 1},
    })


def flat_bspline(p, spans):
    """A flat B-spline of degree p over the unit square, `spans` uniform spans
    each way: the degree, the knot vector and the net at the Greville points."""
    c = spans + p
    knots = [0.0] * (p + 1) + [r(k / spans) for k in range(1, spans)] + [1.0] * (p + 1)
    grev = [sum(knots[i + 1:i + p + 1]) / p for i in range(c)]
    return p, knots, [[[r(grev[i]), r(grev[j]), 0.0] for j in range(c)] for i in range(c)]


def bspline_constraints():
    """tensor_constraints.json's four constraints on a bicubic B-spline of
    10 x 10 uniform spans: the same flat frame, one ring fixed."""
    p, knots, net = flat_bspline(3, 10)
    write("bspline_constraints.json", {
        "name": "Veltkamp & Wesselink's constraints (section 4.1) on a bicubic B-spline: a point, "
                "a normal, a plane and a line",
        "description": "tensor_constraints.json on 10 x 10 uniform knot spans (13 x 13 control "
                       "points), boundary ring fixed on the unit square, thin plate with a little "
                       "membrane; each constraint met exactly through the KKT solve.",
        "surface": {"type": "bspline", "degree": [p, p], "knots": [knots, knots],
                    "control_points": net},
        "fixed_rings": 1,
        "energy": {"stretch": 0.1, "bend": 1},
        "constraints": FOUR_CONSTRAINTS,
    })


def bspline_operators():
    """tensor_operators.json's attractors and director on a bicubic B-spline
    of 10 x 10 uniform spans: the regions cross knot lines."""
    p, knots, net = flat_bspline(3, 10)
    with open(os.path.join(HERE, "tensor_operators.json")) as f:
        operators = json.load(f)["operators"]
    write("bspline_operators.json", {
        "name": "Veltkamp & Wesselink section 5 on a bicubic B-spline: two point attractors, a "
                "director over a region and a plane attractor",
        "description": "tensor_operators.json on 10 x 10 uniform knot spans (13 x 13 control "
                       "points), boundary ring fixed on the unit square, thin plate with a little "
                       "membrane; the regions are integrated exactly span by span.",
        "surface": {"type": "bspline", "degree": [p, p], "knots": [knots, knots],
                    "control_points": net},
        "fixed_rings": 1,
        "energy": {"stretch": 0.1, "bend": 1},
        "operators": operators,
    })


def wave_normal(x, y):
    """The unnormalized normal of the sheet (2u, 2v, wave(u, v)) of bspline_hole:
    (-wave_u / 2, -wave_v / 2, 1)."""
    wave_u = 0.2 * 2.5 * math.pi * math.cos(2.5 * math.pi * x) * math.cos(1.5 * math.pi * y) + 0.3 * y
    wave_v = -0.2 * 1.5 * math.pi * math.sin(2.5 * math.pi * x) * math.sin(1.5 * math.pi * y) + 0.3 * x
    return [-wave_u / 2, -wave_v / 2, 1.0]


def hole_variant(name, title, description, energy):
    """bspline_hole.json with another energy."""
    with open(os.path.join(HERE, "bspline_hole.json")) as f:
        scene = json.load(f)
    scene["name"] = title
    scene["description"] = description
    scene["energy"] = energy
    write(name, scene)


def bspline_hole_guided():
    """bspline_hole with Wu & Yang's normal field: N from the wavy sheet's
    normals (a bicubic Bezier field through them at u, v = i/3), lambda = 100,
    so that the fill follows the sheet it was cut from (their Fig. 4)."""
    field = [[[r(c) for c in wave_normal(i / 3, j / 3)] for j in range(4)] for i in range(4)]
    hole_variant("bspline_hole_guided.json",
                 "Bicubic B-spline hole guided by the sheet's normals (lambda = 100)",
                 "bspline_hole.json with Wu & Yang's normal-field term: N is a bicubic "
                 "Bezier field of the cut sheet's normals, so the fill follows the sheet "
                 "(their Fig. 4, on a B-spline).",
                 {"bend": 1, "normal_field": {"weight": 100, "degree": [3, 3], "control_points": field}})


def bspline_hole_sampled():
    """bspline_hole with the sampled normal field (Wu & Yang eq. 5): the cut
    sheet's exact unit normals at a 44 x 44 grid of the knot domain, lambda =
    100 (their Fig. 4 on a B-spline, with the sheet's own normals)."""
    g = 44
    normals = [[[r(c) for c in unit(wave_normal(i / g, j / g))] for j in range(g + 1)]
               for i in range(g + 1)]
    hole_variant("bspline_hole_sampled.json",
                 "Bicubic B-spline hole guided by the sheet's sampled normals (lambda = 100)",
                 "bspline_hole.json with Wu & Yang's sampled normal-field term (eq. 5): the "
                 "cut sheet's unit normals at 45 x 45 samples of the knot domain, so the "
                 "fill follows the sheet (their Fig. 4, on a B-spline).",
                 {"bend": 1, "normal_field": {"weight": 100},
                  "sampling": {"grid": [g, g], "normal_samples": normals}})


def bspline_hole_field_spline():
    """bspline_hole with a B-spline normal field on its own knots: bicubic on 7
    uniform spans (its knot lines cut the surface's 11 uneven spans), control
    normals the cut sheet's normals at the field's Greville points, lambda = 100
    (their Fig. 4 on a B-spline, with more freedom in N than one cubic)."""
    q, spans = 3, 7
    knots = [0.0] * (q + 1) + [r(k / spans) for k in range(1, spans)] + [1.0] * (q + 1)
    c = spans + q
    grev = [sum(knots[i + 1:i + q + 1]) / q for i in range(c)]
    field = [[[r(x) for x in wave_normal(grev[i], grev[j])] for j in range(c)] for i in range(c)]
    hole_variant("bspline_hole_field_spline.json",
                 "Bicubic B-spline hole guided by a B-spline field of the sheet's normals (lambda = 100)",
                 "bspline_hole.json with Wu & Yang's normal-field term whose N is a B-spline "
                 "on its own knots: bicubic on 7 uniform spans (they cut the surface's 11 "
                 "uneven spans; the term is integrated exactly between both knot sets), "
                 "its control normals the cut sheet's normals at the field's Greville points.",
                 {"bend": 1, "normal_field": {"weight": 100, "knots": [knots, knots],
                                              "control_points": field}})


def split_rows(net, t):
    """de Casteljau along the first index at t: the nets over [0, t] and [t, 1]."""
    n = len(net) - 1
    left, right = [], []
    rows = [row[:] for row in net]
    for k in range(n + 1):
        left.append(rows[0])
        right.append(rows[n - k])
        rows = [[[(1 - t) * a[c] + t * b[c] for c in range(3)] for a, b in zip(rows[i], rows[i + 1])]
                for i in range(len(rows) - 1)]
    return left, right[::-1]


def transpose(net):
    return [list(col) for col in zip(*net)]


def fill_network():
    """A wavy bi-quintic patch cut into 3 x 3 pieces by de Casteljau (a C1
    network: the pieces of one polynomial), the centre piece left out: the hole
    of Wu & Yang's Fig. 4 as a CAD model has it. `fairsurf fill` fills it."""
    big = [[[r(3 * i / 5 + 0.3 * j / 5), r(3 * j / 5),
             r(0.3 * math.sin(3.9 * i / 5) * math.cos(2.7 * j / 5) + 0.45 * i * j / 25)]
            for j in range(6)] for i in range(6)]
    a, rest = split_rows(big, 1 / 3)
    b, c = split_rows(rest, 1 / 2)
    faces = []
    for k, col in enumerate([a, b, c]):
        x, rest = split_rows(transpose(col), 1 / 3)
        y, z = split_rows(rest, 1 / 2)
        for j, piece in enumerate([x, y, z]):
            if (k, j) != (1, 1):
                faces.append({"type": "tensor", "degree": [5, 5], "control_points": transpose(piece)})
    write("cad/fill_network.json", {
        "name": "A hole in a C1 network of bi-quintic patches",
        "description": "Eight bi-quintic Bezier faces cut from one wavy patch, the centre one "
                       "missing. fairsurf fill finds the hole (the inner loop of free edges; the "
                       "outer rim is left alone), builds the fill's two outer rings from the "
                       "neighbours (G1 exactly) and fairs the inside.",
        "faces": faces,
    })


def blend_sheets():
    """Wu & Yang's Fig. 5 as a CAD user has it: two B-spline surfaces of
    different degrees and knots, a gap between an edge of each. `fairsurf
    blend` spans it G1 to both."""
    # A: bicubic, three uneven spans in u, a gentle wave, edge u1 at x = 2.
    ua = [0, 0, 0, 0, 0.3, 0.7, 1, 1, 1, 1]
    na, ma = len(ua) - 4, 4
    a = [[[r(2 * i / (na - 1)), r(1.2 * j / (ma - 1)),
           r(0.15 * math.sin(2.1 * i / (na - 1) + 1.3 * j / (ma - 1)))]
          for j in range(ma)] for i in range(na)]
    # B: biquartic Bezier, tilted up, edge u0 at x = 3 facing A's.
    b = [[[r(3 + 1.5 * i / 4 + 0.1 * j / 4), r(-0.1 + 1.4 * j / 4),
           r(0.9 + 0.8 * i / 4 + 0.1 * math.cos(3.0 * j / 4) * i / 4)]
          for j in range(5)] for i in range(5)]
    write("cad/blend_sheets.json", {
        "name": "A transition surface between two B-spline sheets",
        "description": "A bicubic B-spline sheet (three uneven spans) and a tilted biquartic "
                       "Bezier sheet with a gap between them. fairsurf blend builds the two rings "
                       "on each edge from the surfaces (G1 exactly), makes the two other sides "
                       "cubic Hermite curves, and fairs the inside (Wu & Yang 2015, Fig. 5).",
        "surfaces": [
            {"face": {"type": "bspline", "degree": [3, 3],
                      "knots": [ua, [0, 0, 0, 0, 1, 1, 1, 1]], "control_points": a},
             "edge": "u1"},
            {"face": {"type": "tensor", "degree": [4, 4], "control_points": b}, "edge": "u0"},
        ],
    })


def fill_pentagon():
    """A pentagonal hole in the graph of a cubic, ringed by five bicubic
    patches (each the graph over the quad between a hole side and the
    pentagon of twice the radius). `fairsurf fill` fills it with a fan of five
    triangular patches, G1 to the neighbours and to each other."""
    def f(x, y):
        return 0.3 * x * x - 0.2 * x * y + 0.15 * y * y + 0.1 * x + 0.06 * x ** 3 - 0.05 * x * y * y

    def corner(k, rad):
        a = 2 * math.pi * k / 5 + 0.3
        return (rad * math.cos(a), rad * math.sin(a))

    a = [bern(3, k / 3) for k in range(4)]
    faces = []
    for k in range(5):
        c0, c1, o0, o1 = corner(k, 1), corner(k + 1, 1), corner(k, 2), corner(k + 1, 2)

        def lift(s, t):
            x = (1 - t) * ((1 - s) * c0[0] + s * c1[0]) + t * ((1 - s) * o0[0] + s * o1[0])
            y = (1 - t) * ((1 - s) * c0[1] + s * c1[1]) + t * ((1 - s) * o0[1] + s * o1[1])
            return [x, y, f(x, y)]

        # Interpolate on the 4 x 4 grid: rows first, then columns.
        vals = [[lift(i / 3, j / 3) for j in range(4)] for i in range(4)]
        rows = [[solve_linear(a, [v[c] for v in vals[i]]) for c in range(3)] for i in range(4)]
        net = [[[r(solve_linear(a, [rows[i][c][j] for i in range(4)])[ii]) for c in range(3)]
                for j in range(4)] for ii in range(4)]
        faces.append({"type": "tensor", "degree": [3, 3], "control_points": net})
    write("cad/fill_pentagon.json", {
        "name": "A pentagonal hole in a ring of bicubic patches",
        "description": "Five bicubic Bezier faces, pieces of one smooth graph, around a "
                       "pentagonal hole. fairsurf fill fills it with a fan of five triangular "
                       "patches around a free centre: the rows next to each side from the "
                       "neighbour (G1 exactly), Veltkamp & Wesselink's G1 conditions between the "
                       "fan's patches, the thin plate inside.",
        "faces": faces,
    })


def fill_round(turn=0.0, every=False):
    """A round hole (four C1 cubic quarter-circle arcs of radius 1, no corner)
    in the graph of a quadratic, ringed by four faces out to radius 2 that are
    exact pieces of it (degree 6 along the arcs, 2 across). `fairsurf fill`
    fills it with a fan of four triangular patches around a free centre, G1 to
    the neighbours and between the patches. With `turn` (radians) the first
    arc's first handle is turned inwards by it: one real corner, three
    straight ones (fill_notch.json); with `every`, both handles of every arc:
    four real corners where the faces' radial edges do not continue the
    hole's sides (fill_corners.json)."""
    def f(x, y):
        return 0.15 * x * y + 0.1 * x * x - 0.08 * y * y

    k = 4 / 3 * math.tan(math.pi / 8)

    def arc(q, s):
        a0, a1 = q * math.pi / 2 + 0.2, (q + 1) * math.pi / 2 + 0.2
        p0 = (math.cos(a0), math.sin(a0))
        p3 = (math.cos(a1), math.sin(a1))
        t = (-p0[1], p0[0])
        e = (-p3[1], p3[0])
        c, sn = math.cos(turn), math.sin(turn)
        if q == 0 or every:
            t = (t[0] * c - t[1] * sn, t[0] * sn + t[1] * c)
        if every:
            e = (e[0] * c + e[1] * sn, -e[0] * sn + e[1] * c)
        p1 = (p0[0] + k * t[0], p0[1] + k * t[1])
        p2 = (p3[0] - k * e[0], p3[1] - k * e[1])
        b = bern(3, s)
        return tuple(sum(b[i] * pt[c] for i, pt in enumerate((p0, p1, p2, p3))) for c in range(2))

    def piece(q):
        # (u, v) -> ((1 + v) arc(u), f): degree 6 in u, 2 in v; interpolation
        # on the 7 x 3 grid gives its net exactly.
        du, dv = 6, 2
        au = [bern(du, i / du) for i in range(du + 1)]
        av = [bern(dv, j / dv) for j in range(dv + 1)]
        vals = []
        for i in range(du + 1):
            row = []
            for j in range(dv + 1):
                x, y = arc(q, i / du)
                x, y = (1 + j / dv) * x, (1 + j / dv) * y
                row.append([x, y, f(x, y)])
            vals.append(row)
        rows = [[solve_linear(av, [vals[i][j][c] for j in range(dv + 1)]) for c in range(3)]
                for i in range(du + 1)]
        net = [[[r(solve_linear(au, [rows[i][c][j] for i in range(du + 1)])[ii]) for c in range(3)]
                for j in range(dv + 1)] for ii in range(du + 1)]
        return {"type": "tensor", "degree": [du, dv], "control_points": net}

    if every:
        name, title, what = "fill_corners", \
            "A 4-sided hole whose neighbours' edges do not continue its sides", \
            ("around a hole bounded by four cubic arcs whose ends are turned inwards by %.2f "
             "rad: four real corners, where the faces meet along radial edges that do not "
             "continue the hole's sides. One tensor patch misses those faces by degrees (its "
             "corners take the adjacent sides' directions); fairsurf fill cuts the longest arc "
             "at its middle and fills the hole with a fan of five triangular patches, G1 to "
             "the neighbours and between the patches." % turn)
    elif turn:
        name, title, what = "fill_notch", "A hole with one corner in a ring of four faces", \
            ("around a hole bounded by four cubic arcs: three meet C1, the first starts turned "
             "by %.2f rad (one real corner). fairsurf fill cuts the longest arc (by control "
             "polygon) at its middle and fills the hole with a fan of five triangular patches "
             "around a free centre, natural spokes, G1 to the neighbours and between the "
             "patches." % turn)
    else:
        name, title, what = "fill_round", "A round hole in a ring of four faces", \
            ("around a round hole bounded by four cubic quarter-circle arcs that meet C1 (no "
             "corner). fairsurf fill fills it with a fan of four triangular patches around a "
             "free centre, their rows next to the boundary cubic in their weights, G1 to the "
             "neighbours and between the patches.")
    write("cad/%s.json" % name, {
        "name": title,
        "description": "Four faces of degree 6 x 2, exact pieces of one quadratic graph, " + what,
        "faces": [piece(q) for q in range(4)],
    })


def fill_lens():
    """A hole of two sides (a lens between the parabolas y = +-0.4 (1 - x^2))
    in the graph of a quadratic, ringed by four biquartic patches that are
    exact pieces of it. `fairsurf fill` cuts the two sides at their middles and
    fills it with a fan of four triangular patches, G1 to the neighbours and
    to each other."""
    def f(x, y):
        return 0.15 * x * y + 0.1 * x * x - 0.08 * y * y

    def h(x):
        return 0.4 * (1 - x * x)

    a = [bern(4, k / 4) for k in range(5)]

    def piece(xy):
        # The map (u, v) -> (x, y, f) is polynomial of degree <= 4 in each
        # parameter: interpolation on the 5 x 5 grid gives its net.
        vals = [[xy(i / 4, j / 4) for j in range(5)] for i in range(5)]
        vals = [[[x, y, f(x, y)] for (x, y) in row] for row in vals]
        rows = [[solve_linear(a, [v[c] for v in vals[i]]) for c in range(3)] for i in range(5)]
        net = [[[r(solve_linear(a, [rows[i][c][j] for i in range(5)])[ii]) for c in range(3)]
                for j in range(5)] for ii in range(5)]
        return {"type": "tensor", "degree": [4, 4], "control_points": net}

    def x_of(u):
        return -1 + 2 * u

    faces = [
        piece(lambda u, v: (x_of(u), -1 + v * (1 - h(x_of(u))))),
        piece(lambda u, v: (x_of(u), h(x_of(u)) + v * (1 - h(x_of(u))))),
        piece(lambda u, v: (-2 + u, -1 + 2 * v)),
        piece(lambda u, v: (1 + u, -1 + 2 * v)),
    ]
    write("cad/fill_lens.json", {
        "name": "A hole of two sides (a lens) in a ring of biquartic patches",
        "description": "Four biquartic Bezier faces, exact pieces of one quadratic graph, around "
                       "a lens-shaped hole bounded by two parabolic edges that meet at two "
                       "corners. fairsurf fill cuts both sides at their middles (two straight "
                       "corners) and fills the hole with a fan of four triangular patches around "
                       "a free centre, G1 to the neighbours and between the patches.",
        "faces": faces,
    })


# Wu & Yang Fig. 1-5 on bicubic B-splines (issue 19): the same setups at a
# designer's resolution, uniform knots, the net over the Greville abscissae.

def uniform_knots(c, p=3):
    spans = c - p
    return [0.0] * (p + 1) + [k / spans for k in range(1, spans)] + [1.0] * (p + 1)


def greville(knots, c, p=3):
    return [sum(knots[i + 1:i + p + 1]) / p for i in range(c)]


def bspline_basis(knots, p, c, t):
    """N_i,p(t) for i < c (Cox-de Boor; t = 1 in the last span)."""
    t = min(max(t, knots[p]), knots[c])
    n = [1.0 if (knots[i] <= t < knots[i + 1]) or (t == knots[c] and knots[i] < t == knots[i + 1])
         else 0.0 for i in range(len(knots) - 1)]
    for d in range(1, p + 1):
        n = [((t - knots[i]) / (knots[i + d] - knots[i]) * n[i] if knots[i + d] > knots[i] else 0.0)
             + ((knots[i + d + 1] - t) / (knots[i + d + 1] - knots[i + 1]) * n[i + 1]
                if knots[i + d + 1] > knots[i + 1] else 0.0)
             for i in range(len(knots) - d - 1)]
    return n[:c]


def bspline_point(net, knots, u, v, p=3):
    c = len(net)
    bu, bv = bspline_basis(knots, p, c, u), bspline_basis(knots, p, c, v)
    return [sum(bu[i] * bv[j] * net[i][j][k] for i in range(c) for j in range(c) if bu[i] and bv[j])
            for k in range(3)]


def bspline_normal(net, knots, u, v, h=1e-6):
    """The unit normal by central differences (one-sided at the domain's ends)."""
    def d(f, x):
        a, b = max(x - h, 0.0), min(x + h, 1.0)
        return [(q - p_) / (b - a) for p_, q in zip(f(a), f(b))]
    su = d(lambda x: bspline_point(net, knots, x, v), u)
    sv = d(lambda y: bspline_point(net, knots, u, y), v)
    return unit(cross(su, sv))


def bspline_graph(c, f):
    """c x c bicubic net over [0, 1]^2: x, y the Greville abscissae, z = f there."""
    knots = uniform_knots(c)
    g = greville(knots, c)
    return knots, [[[g[i], g[j], f(g[i], g[j])] for j in range(c)] for i in range(c)]


def bspline_scene(title, description, knots, net, rings, energy):
    return {
        "name": title,
        "description": description,
        "surface": {"type": "bspline", "degree": [3, 3], "knots": [knots, knots],
                    "control_points": clean(net)},
        "fixed_rings": rings,
        "energy": energy,
    }


def truth_file(name, title, knots, net):
    """A ground truth as a B-spline scene with every point given (read, not solved)."""
    write(name, bspline_scene(title, "Every control point given: the surface the fill is "
                              "measured against.", knots, net, 2, {"bend": 1}))


def ringed_truth(c, g, f, slope, fig, title):
    """A c x c bicubic truth over the graph of f (written to data/ as the fill's
    ground truth), the net with its two outer rings and the inside on the plane
    z = slope x, and the truth's unit normals at (g + 1)^2 samples."""
    knots, truth = bspline_graph(c, f)
    truth_file(f"data/bspline_wu_yang_{fig}_ground_truth.json", title, knots, truth)
    init = [[list(q) for q in row] for row in truth]
    for i in range(2, c - 2):
        for j in range(2, c - 2):
            init[i][j][2] = slope * init[i][j][0]
    normals = [[[r(q) for q in bspline_normal(truth, knots, i / g, j / g)] for j in range(g + 1)]
               for i in range(g + 1)]
    return knots, init, normals


def bspline_wu_yang():
    # Fig. 1: the extended membrane with a Bezier field of a ridge, and the guide.
    c = 16
    knots, init = bspline_graph(c, lambda x, y: 0.25 * math.sin(math.pi * x) * math.sin(math.pi * y))
    ridge = graph_net(5, 5, lambda x, y: 0.5 * math.exp(-12 * (x - 0.5) ** 2) * math.sin(math.pi * y))
    field = [[[r(q) for q in patch_normal(ridge, i / 5, j / 5)] for j in range(6)] for i in range(6)]
    for lam, gam in [(10, 0), (10, 100)]:
        energy = {"stretch": 1, "normal_field": {"weight": lam, "degree": [5, 5], "control_points": field}}
        if gam:
            energy["guide_surface"] = {"weight": gam}
        write(f"bspline_wu_yang_fig1_l{lam}_g{gam}.json", bspline_scene(
            f"Wu & Yang Fig. 1 on a bicubic B-spline (16 x 16): lambda = {lam}, gamma = {gam}",
            "wu_yang_fig1 at a designer's resolution: 13 x 13 uniform spans, boundary fixed, the "
            "degree-5 Bezier field of a ridge; the guide (gamma > 0) is the initial dome.",
            knots, init, 1, energy))
    # Fig. 2 and 3: the hat with a wavy brim, sampled normals (flat top; a cone's).
    c, g = 20, 40
    knots, init = bspline_graph(c, hat)
    def graph_normal(f, x, y, h=1e-6):
        fx = (f(x + h, y) - f(x - h, y)) / (2 * h)
        fy = (f(x, y + h) - f(x, y - h)) / (2 * h)
        return unit([-fx, -fy, 1.0])
    flat = [[[r(q) for q in ([0.0, 0.0, 1.0] if math.hypot(i / g - 0.5, j / g - 0.5) < 0.22
                             else bspline_normal(init, knots, i / g, j / g))]
             for j in range(g + 1)] for i in range(g + 1)]
    write("bspline_wu_yang_fig2_l10.json", bspline_scene(
        "Wu & Yang Fig. 2 on a bicubic B-spline (20 x 20): sampled membrane, lambda = 10",
        "The hat with a wavy brim at 17 x 17 spans; 41 x 41 sampled unit normals, vertical on "
        "the top (flatten it), the initial surface's elsewhere.",
        knots, init, 1,
        {"stretch": 1, "normal_field": {"weight": 10},
         "sampling": {"grid": [g, g], "normal_samples": flat}}))
    cone = lambda x, y: 0.7 * max(0.0, 1 - 2.2 * math.hypot(x - 0.5, y - 0.5))
    cone_normals = [[[r(q) for q in graph_normal(cone, i / g, j / g)] for j in range(g + 1)]
                    for i in range(g + 1)]
    write("bspline_wu_yang_fig3_l50.json", bspline_scene(
        "Wu & Yang Fig. 3 on a bicubic B-spline (20 x 20): toward a cone, lambda = 50",
        "The same hat; 41 x 41 sampled unit normals of a cone (its apex's normal taken "
        "vertical where the slope is undefined).",
        knots, init, 1,
        {"stretch": 1, "normal_field": {"weight": 50},
         "sampling": {"grid": [g, g], "normal_samples": cone_normals}}))
    # Fig. 4: hole filling; two rings of a ridged truth kept, the inside starts on a plane.
    c, g = 20, 40
    truth_f = lambda x, y: (0.5 * math.exp(-30 * (x - y) ** 2) * math.sin(math.pi * x)
                            * math.sin(math.pi * y) + 0.15 * x)
    knots, init, normals = ringed_truth(c, g, truth_f, 0.15, "fig4",
                                        "Wu & Yang Fig. 4 on a bicubic B-spline: the ground truth")
    for lam in [0, 500]:
        energy = {"bend": 1}
        if lam:
            energy["normal_field"] = {"weight": lam}
            energy["sampling"] = {"grid": [g, g], "normal_samples": normals}
        write(f"bspline_wu_yang_fig4_l{lam}.json", bspline_scene(
            f"Wu & Yang Fig. 4 on a bicubic B-spline (20 x 20): hole filling, lambda = {lam}",
            "Two outer rings of a ridged truth fixed (G1 to the surroundings), the 16 x 16 "
            "inside starts on a plane; the truth's sampled normals (41 x 41) guide the fill.",
            knots, init, 2, energy))
    # Fig. 5: a transition between a floor and a shelf with a wavy shoulder.
    c, g = 16, 32
    step = lambda x, y: 0.5 / (1 + math.exp(-14 * (x - 0.5 - 0.12 * math.sin(2 * math.pi * y))))
    knots, init, normals = ringed_truth(c, g, step, 0.5, "fig5",
                                        "Wu & Yang Fig. 5 on a bicubic B-spline: the wavy step")
    write("bspline_wu_yang_fig5_l500.json", bspline_scene(
        "Wu & Yang Fig. 5 on a bicubic B-spline (16 x 16): transition, lambda = 500",
        "Two outer rings fixed (G1 to the floor and the shelf it joins); the wavy step's "
        "sampled normals (33 x 33) guide the blend.",
        knots, init, 2,
        {"bend": 1, "normal_field": {"weight": 500},
         "sampling": {"grid": [g, g], "normal_samples": normals}}))
    write("bspline_wu_yang_fig5_thin_plate.json", bspline_scene(
        "Wu & Yang Fig. 5(b) on a bicubic B-spline (16 x 16): the plain thin plate",
        "The same transition by the thin-plate energy alone.",
        knots, init, 2, {"bend": 1}))


if __name__ == "__main__":
    bspline_wu_yang()
    fill_pentagon()
    fill_lens()
    fill_round()
    fill_round(0.3)
    fill_round(0.4, every=True)
    blend_sheets()
    fill_network()
    bspline_hole()
    bspline_hole_guided()
    bspline_hole_sampled()
    bspline_hole_field_spline()
    bspline_constraints()
    editor_degree10()
    tensor_operators()
    bspline_operators()
    monterde_ugail()
    quickstart()
    fig1()
    fig2_3()
    fig4()
    fig5()
