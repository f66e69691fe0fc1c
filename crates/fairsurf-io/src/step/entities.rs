//! The STEP entities of a shell, written into [`Data`]: points, B-spline
//! surfaces and curves, edges shared between faces, loops, faces, the shell
//! and its product context.

use super::*;

impl Data {
    pub(super) fn add(&mut self, entity: impl std::fmt::Display) -> usize {
        self.next += 1;
        let _ = writeln!(self.text, "#{}={};", self.next, entity);
        self.next
    }

    /// Application context, product, its definition and shape, units and
    /// the representation context (the usual AP214 skeleton).
    pub(super) fn header_entities(&mut self) -> Context {
        let app =
            self.add("APPLICATION_CONTEXT('core data for automotive mechanical design processes')");
        self.add(format_args!(
            "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#{app})"
        ));
        let pc = self.add(format_args!("PRODUCT_CONTEXT('',#{app},'mechanical')"));
        let product = self.add(format_args!(
            "PRODUCT('fairsurf','fairsurf surface','',(#{pc}))"
        ));
        self.add(format_args!(
            "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#{product}))"
        ));
        let pdf = self.add(format_args!(
            "PRODUCT_DEFINITION_FORMATION('','',#{product})"
        ));
        let pdc = self.add(format_args!(
            "PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')"
        ));
        let pd = self.add(format_args!(
            "PRODUCT_DEFINITION('design','',#{pdf},#{pdc})"
        ));
        let shape = self.add(format_args!("PRODUCT_DEFINITION_SHAPE('','',#{pd})"));
        let mm = self.add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
        let rad = self.add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))");
        let sr = self.add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())");
        let unc = self.add(format_args!(
            "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.0E-7),#{mm},\
             'distance_accuracy_value','confusion accuracy')"
        ));
        let representation = self.add(format_args!(
            "(GEOMETRIC_REPRESENTATION_CONTEXT(3)\
             GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{unc}))\
             GLOBAL_UNIT_ASSIGNED_CONTEXT((#{mm},#{rad},#{sr}))\
             REPRESENTATION_CONTEXT('fairsurf','3D'))"
        ));
        Context {
            representation,
            shape,
        }
    }

    /// The ADVANCED_FACE of one surface (with its surface, edges and vertices).
    pub(super) fn face(&mut self, s: &CadSurface) -> usize {
        let ((n, m), (cu, cv)) = (s.degree, s.counts);
        let points: Vec<usize> = s
            .points
            .iter()
            .map(|&p| self.add(format_args!("CARTESIAN_POINT('',{})", coords(p))))
            .collect();
        let id = |i: usize, j: usize| points[i * cv + j];
        let rows: Vec<String> = (0..cu)
            .map(|i| format!("({})", refs(&(0..cv).map(|j| id(i, j)).collect::<Vec<_>>())))
            .collect();
        let (ku, mu) = s.distinct_knots(0);
        let (kv, mv) = s.distinct_knots(1);
        let surface = match &s.weights {
            None => self.add(format_args!(
                "B_SPLINE_SURFACE_WITH_KNOTS('',{n},{m},({}),.UNSPECIFIED.,.F.,.F.,.F.,\
                 ({}),({}),({}),({}),.UNSPECIFIED.)",
                rows.join(","),
                ints(&mu),
                ints(&mv),
                reals(&ku),
                reals(&kv)
            )),
            // A complex instance, its partial entities in alphabetical order
            // (ISO 10303-21 §11.2.5.3), as Open CASCADE writes it.
            Some(w) => {
                let weights: Vec<String> = (0..cu)
                    .map(|i| format!("({})", reals(&w[i * cv..(i + 1) * cv])))
                    .collect();
                self.add(format_args!(
                    "(BOUNDED_SURFACE() B_SPLINE_SURFACE({n},{m},({}),.UNSPECIFIED.,.F.,.F.,.F.) \
                     B_SPLINE_SURFACE_WITH_KNOTS(({}),({}),({}),({}),.UNSPECIFIED.) \
                     GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE(({})) \
                     REPRESENTATION_ITEM('') SURFACE())",
                    rows.join(","),
                    ints(&mu),
                    ints(&mv),
                    reals(&ku),
                    reals(&kv),
                    weights.join(",")
                ))
            }
        };
        if !s.loops.is_empty() {
            return self.trimmed_face(s, surface);
        }
        // Counter-clockwise in (u, v): v = 0 and u = 1 along their parameter,
        // v = 1 and u = 0 against it. Each side: (i, j) in parameter order,
        // with the knots of its direction.
        // (i, j) of each side in parameter order, forward or not, direction.
        type Side = (Vec<(usize, usize)>, bool, usize);
        let sides: [Side; 4] = [
            ((0..cu).map(|i| (i, 0)).collect(), true, 0),
            ((0..cv).map(|j| (cu - 1, j)).collect(), true, 1),
            ((0..cu).map(|i| (i, cv - 1)).collect(), false, 0),
            ((0..cv).map(|j| (0, j)).collect(), false, 1),
        ];
        let mut oriented = Vec::new();
        for (side, forward, dir) in &sides {
            let pts: Vec<Vec3> = side.iter().map(|&(i, j)| s.point(i, j)).collect();
            let ids: Vec<usize> = side.iter().map(|&(i, j)| id(i, j)).collect();
            let (d, knots, mults) = if *dir == 0 {
                (n, &ku, &mu)
            } else {
                (m, &kv, &mv)
            };
            let curve = SideCurve {
                d,
                knots,
                mults,
                full: &s.knots[*dir],
                weights: s
                    .weights
                    .as_ref()
                    .map(|_| side.iter().map(|&(i, j)| s.weight(i, j)).collect()),
            };
            let mut edges = self.edges_along(&pts, &ids, &curve);
            if !forward {
                edges.reverse();
            }
            for (edge, same) in edges {
                let sense = if same == *forward { ".T." } else { ".F." };
                oriented.push(self.add(format_args!("ORIENTED_EDGE('',*,*,#{edge},{sense})")));
            }
        }
        let bound = if oriented.is_empty() {
            // Every side collapsed: the whole boundary is one point.
            let v = self.vertex(s.point(0, 0), id(0, 0));
            self.add(format_args!("VERTEX_LOOP('',#{v})"))
        } else {
            self.add(format_args!("EDGE_LOOP('',({}))", refs(&oriented)))
        };
        let outer = self.add(format_args!("FACE_OUTER_BOUND('',#{bound},.T.)"));
        self.add(format_args!("ADVANCED_FACE('',(#{outer}),#{surface},.T.)"))
    }

    /// The ADVANCED_FACE of a trimmed surface (its SURFACE entity
    /// `surface` written): its loops' curves as edges, shared as sides
    /// are ([`Self::edges_along`]), each loop a FACE_BOUND (which one is
    /// outer is not known: readers tell by the loops' sense).
    fn trimmed_face(&mut self, s: &CadSurface, surface: usize) -> usize {
        let mut bounds = Vec::with_capacity(s.loops.len());
        for l in &s.loops {
            let mut oriented = Vec::new();
            for c in l {
                let ids: Vec<usize> = c
                    .points
                    .iter()
                    .map(|&p| self.add(format_args!("CARTESIAN_POINT('',{})", coords(p))))
                    .collect();
                let (knots, mults) = crate::cad::distinct(&c.knots);
                let curve = SideCurve {
                    d: c.degree,
                    knots: &knots,
                    mults: &mults,
                    full: &c.knots,
                    weights: None,
                };
                for (edge, same) in self.edges_along(&c.points, &ids, &curve) {
                    let sense = if same { ".T." } else { ".F." };
                    oriented.push(self.add(format_args!("ORIENTED_EDGE('',*,*,#{edge},{sense})")));
                }
            }
            let edges = self.add(format_args!("EDGE_LOOP('',({}))", refs(&oriented)));
            bounds.push(self.add(format_args!("FACE_BOUND('',#{edges},.T.)")));
        }
        self.add(format_args!(
            "ADVANCED_FACE('',({}),#{surface},.T.)",
            refs(&bounds)
        ))
    }

    /// The EDGE_CURVEs along one side (in its parameter order, each with
    /// whether it runs that way): the side's own edge, shared when another
    /// face wrote it; or, when vertices written before lie
    /// inside the side (neighbours whose edges cover parts of it, e.g. two
    /// faces along one side of a fill), one edge between each two
    /// consecutive vertices on the side's curve, shared with an edge
    /// written before that joins the same vertices along the same curve.
    /// Empty for a collapsed side.
    pub(super) fn edges_along(
        &mut self,
        pts: &[Vec3],
        ids: &[usize],
        curve: &SideCurve,
    ) -> Vec<(usize, bool)> {
        if pts.iter().all(|&p| bits(p) == bits(pts[0])) {
            return Vec::new();
        }
        if let Some(found) = self.known_edge(pts, curve) {
            return vec![found];
        }
        let Ok(kv) = fairsurf::bspline::KnotVector::new(curve.d, curve.full.clone()) else {
            return vec![self.new_edge(pts, ids, curve)];
        };
        let w = curve.weights.as_deref();
        let tol = self.tol;
        let last = pts.len() - 1;
        let (a, b) = kv.domain();
        // Vertices written before that lie inside the side: within the
        // control polygon's box (the curve lies in it), off its ends.
        let (lo, hi) = pts
            .iter()
            .fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), p| {
                (
                    std::array::from_fn(|c| lo[c].min(p[c] - tol)),
                    std::array::from_fn(|c| hi[c].max(p[c] + tol)),
                )
            });
        // Vertices written, and corners of faces still to come.
        let candidates = self
            .vertex_points
            .iter()
            .map(|&(q, v)| (q, Some(v)))
            .chain(self.corners.iter().map(|&q| (q, None)));
        let mut found: Vec<(f64, Vec3, Option<usize>)> = candidates
            .filter(|(q, _)| (0..3).all(|c| q[c] >= lo[c] && q[c] <= hi[c]))
            .filter(|(q, _)| dist(*q, pts[0]) > tol && dist(*q, pts[last]) > tol)
            .filter_map(|(q, v)| {
                let t = project(&kv, pts, w, q)?;
                (t > a && t < b && dist(curve_point(&kv, pts, w, t), q) <= tol).then_some((t, q, v))
            })
            .collect();
        // Written vertices first, then by parameter, each point once.
        found.sort_by_key(|x| x.2.is_none());
        let mut unique: Vec<(f64, Vec3, Option<usize>)> = Vec::new();
        for f in found {
            if !unique.iter().any(|u| dist(u.1, f.1) <= tol) {
                unique.push(f);
            }
        }
        if unique.is_empty() {
            return vec![self.new_edge(pts, ids, curve)];
        }
        unique.sort_by(|x, y| x.0.total_cmp(&y.0));
        let inside: Vec<(f64, usize)> = unique
            .into_iter()
            .map(|(t, q, v)| {
                let v = v.unwrap_or_else(|| {
                    let point = self.add(format_args!("CARTESIAN_POINT('',{})", coords(q)));
                    self.vertex(q, point)
                });
                (t, v)
            })
            .collect();
        let start = self.vertex(pts[0], ids[0]);
        let end = self.vertex(pts[last], ids[last]);
        let mut chain = vec![(a, start)];
        chain.extend(inside);
        chain.push((b, end));
        let mut out = Vec::new();
        for pair in chain.windows(2) {
            let ((ta, va), (tb, vb)) = (pair[0], pair[1]);
            let samples: [Vec3; EDGE_SAMPLES] = std::array::from_fn(|k| {
                curve_point(
                    &kv,
                    pts,
                    w,
                    ta + (tb - ta) * k as f64 / (EDGE_SAMPLES - 1) as f64,
                )
            });
            if let Some(found) = self.matching_edge(&samples) {
                out.push(found);
                continue;
            }
            // Each piece its own curve, cut exactly at the vertices (a
            // reader that projects the vertices onto a longer curve finds
            // their parameters only to its own tolerance: Open CASCADE put
            // them 3e-8 off).
            let (c, written) = match cut_curve(&kv, pts, w, ta, tb) {
                Some((k, piece, weights)) => {
                    let ids: Vec<usize> = piece
                        .iter()
                        .map(|&p| self.add(format_args!("CARTESIAN_POINT('',{})", coords(p))))
                        .collect();
                    let (knots, mults) = crate::cad::distinct(k.knots());
                    let c = self.add(
                        SideCurve {
                            d: k.degree(),
                            knots: &knots,
                            mults: &mults,
                            full: &k.knots().to_vec(),
                            weights: weights.clone(),
                        }
                        .entity(&ids),
                    );
                    (c, (k, piece, weights))
                }
                None => (
                    self.add(curve.entity(ids)),
                    (kv.clone(), pts.to_vec(), curve.weights.clone()),
                ),
            };
            let e = self.add(format_args!("EDGE_CURVE('',#{va},#{vb},#{c},.T.)"));
            let (knots, points, weights) = written;
            self.edge_samples.push(WrittenEdge {
                samples,
                edge: e,
                knots,
                points,
                weights,
            });
            out.push((e, true));
        }
        out
    }

    /// An edge written before along the same curve as `pts` (by its
    /// points and knots, or by its samples), and whether it runs the same
    /// way.
    pub(super) fn known_edge(&self, pts: &[Vec3], curve: &SideCurve) -> Option<(usize, bool)> {
        for (reversed, same) in [(false, true), (true, false)] {
            if let Some(&e) = self.edges.get(&curve.key(pts, reversed)) {
                return Some((e, same));
            }
        }
        self.matching_edge(&curve.samples(pts)?)
    }

    /// An edge written before through `samples` (first to last, or last to
    /// first), and whether it runs the same way: at the same parameters,
    /// or — a curve parametrized otherwise, as a cylinder's rational arc
    /// and a trimmed cap's polynomial stand-in of it — with the same ends
    /// and every sample within the tolerance of the written curve (its
    /// nearest point), their parameters on it running one way: the way
    /// they run tells the sense (a closed edge's ends do not).
    pub(super) fn matching_edge(&self, samples: &[Vec3; EDGE_SAMPLES]) -> Option<(usize, bool)> {
        let tol = self.tol;
        let close = |a: &[Vec3], b: &mut dyn Iterator<Item = Vec3>| {
            a.iter().zip(b).all(|(p, q)| dist(*p, q) <= tol)
        };
        for w in &self.edge_samples {
            if close(&w.samples, &mut samples.iter().copied()) {
                return Some((w.edge, true));
            }
            if close(&w.samples, &mut samples.iter().rev().copied()) {
                return Some((w.edge, false));
            }
        }
        let last = EDGE_SAMPLES - 1;
        // The written curve's parameters of the samples inside, each on it
        // within the tolerance: rising when the edge runs the curve's way,
        // falling when it runs back (a closed edge's ends tell nothing).
        let run = |w: &WrittenEdge| -> Option<bool> {
            let weights = w.weights.as_deref();
            let t: Vec<f64> = samples[1..last]
                .iter()
                .map(|&q| {
                    project(&w.knots, &w.points, weights, q)
                        .filter(|&t| dist(curve_point(&w.knots, &w.points, weights, t), q) <= tol)
                })
                .collect::<Option<_>>()?;
            if t.windows(2).all(|p| p[1] > p[0]) {
                Some(true)
            } else if t.windows(2).all(|p| p[1] < p[0]) {
                Some(false)
            } else {
                None
            }
        };
        self.edge_samples.iter().find_map(|w| {
            let ends = |a: usize, b: usize| {
                dist(w.samples[0], samples[a]) <= tol && dist(w.samples[last], samples[b]) <= tol
            };
            let (forward, back) = (ends(0, last), ends(last, 0));
            if !(forward || back) {
                return None;
            }
            let same = run(w)?;
            (if same { forward } else { back }).then_some((w.edge, same))
        })
    }

    /// A new EDGE_CURVE along the control polygon `pts` (CARTESIAN_POINTs
    /// `ids`) of degree d with distinct knots and multiplicities, from the
    /// polygon's first point to its last, registered for sharing.
    pub(super) fn new_edge(
        &mut self,
        pts: &[Vec3],
        ids: &[usize],
        side: &SideCurve,
    ) -> (usize, bool) {
        let curve = self.add(side.entity(ids));
        let last = pts.len() - 1;
        let start = self.vertex(pts[0], ids[0]);
        let end = self.vertex(pts[last], ids[last]);
        let e = self.add(format_args!("EDGE_CURVE('',#{start},#{end},#{curve},.T.)"));
        self.edges.insert(side.key(pts, false), e);
        if let (Some(samples), Ok(knots)) = (
            side.samples(pts),
            fairsurf::bspline::KnotVector::new(side.d, side.full.clone()),
        ) {
            self.edge_samples.push(WrittenEdge {
                samples,
                edge: e,
                knots,
                points: pts.to_vec(),
                weights: side.weights.clone(),
            });
        }
        (e, true)
    }

    /// The VERTEX_POINT at `p` (a CARTESIAN_POINT `point`), shared by all
    /// corners at the same point.
    pub(super) fn vertex(&mut self, p: Vec3, point: usize) -> usize {
        if let Some(&v) = self.vertices.get(&bits(p)) {
            return v;
        }
        let tol = self.tol;
        let near = self.vertex_points.iter().find(|(q, _)| dist(p, *q) <= tol);
        if let Some(&(_, v)) = near {
            return v;
        }
        let v = self.add(format_args!("VERTEX_POINT('',#{point})"));
        self.vertices.insert(bits(p), v);
        self.vertex_points.push((p, v));
        v
    }
}
