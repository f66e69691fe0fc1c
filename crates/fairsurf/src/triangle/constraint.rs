//! Linear constraints on a triangular surface (Veltkamp & Wesselink §4 and
//! eq. 31, F P = G): point, normal, point-in-plane and point-on-line
//! interpolation at a point of the domain, and fixed control points.
//!
//! Every constraint becomes rows over the 3N coordinates of the surface's N
//! global control points, coordinate c of point g at index 3g + c:
//!
//! ```text
//! point     T(p) = P                Σ_J B_J(p) P_J = P                      3 rows
//! normal    N·∂T/∂u = N·∂T/∂v = 0   eq. (8), w = 1 − u − v                  2 rows
//! in plane  n·T(p) = a                                                      1 row
//! on line   T(p) on {Q + s d}       a₁·T(p) = a₁·Q, a₂·T(p) = a₂·Q, a₁,a₂ ⊥ d  2 rows
//! fixed     P_g = value             eliminated before the solve             3 coordinates
//! ```
//!
//! B_J are the degree-n triangular Bernstein polynomials of the patch that
//! holds p; J runs over its control points, mapped to globals.

use super::bernstein::{tri_bernstein_all, Bary};
use super::index::multi_indices;
use super::refine::{check_point, DomainPoint};
use super::surface::TriSurface;
use crate::vec3::{angle, cross, dot, is_finite, norm, normalize, scale, sub, Vec3};
use crate::{Error, Result};

/// One linear constraint of a triangular surface (eq. 31).
#[derive(Clone, Debug, PartialEq)]
pub enum Constraint {
    /// The surface passes through `target` at `at`: T(u₀, v₀, w₀) = P (§4.1).
    Point {
        /// Where in the domain.
        at: DomainPoint,
        /// The point to interpolate.
        target: Vec3,
    },
    /// The surface normal at `at` is `normal` (eq. 8: N·∂T/∂u = N·∂T/∂v = 0);
    /// up to sign, since the equations are linear.
    Normal {
        /// Where in the domain.
        at: DomainPoint,
        /// The normal direction (any length but zero).
        normal: Vec3,
    },
    /// The surface point at `at` lies in the plane n·x = a (§4.1).
    InPlane {
        /// Where in the domain.
        at: DomainPoint,
        /// The plane's normal n (any length but zero).
        normal: Vec3,
        /// Its offset a (with n as given).
        offset: f64,
    },
    /// The surface point at `at` lies on the line through `point` along
    /// `direction` (two point-in-plane constraints, §4.1).
    OnLine {
        /// Where in the domain.
        at: DomainPoint,
        /// A point of the line.
        point: Vec3,
        /// Its direction (any length but zero).
        direction: Vec3,
    },
    /// The global control point `point` keeps `value` (§6: eliminated from
    /// the minimization).
    Fixed {
        /// Global control point index.
        point: usize,
        /// Its value.
        value: Vec3,
    },
}

/// A constraint with the name reports use (e.g. `constraints[2] (point)`).
#[derive(Clone, Debug, PartialEq)]
pub struct NamedConstraint {
    /// How reports call it.
    pub name: String,
    /// What it requires.
    pub constraint: Constraint,
}

/// One linear equation Σ a_i x_i = rhs over the 3N coordinates (index
/// 3g + c), with the name of the constraint it comes from.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// (coordinate index, coefficient), each index once.
    pub terms: Vec<(usize, f64)>,
    /// The right-hand side.
    pub rhs: f64,
    /// Which constraint (and which of its equations).
    pub name: String,
}

impl Row {
    /// Σ a_i x_i − rhs for the coordinates x (index 3g + c).
    pub fn residual(&self, x: &[f64]) -> f64 {
        self.terms.iter().map(|&(i, a)| a * x[i]).sum::<f64>() - self.rhs
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl Constraint {
    /// Checks the constraint against the surface: its patch exists, its
    /// barycentrics lie in the triangle, its vectors are finite and not zero.
    /// The error names the constraint.
    pub fn validate(&self, surface: &TriSurface, name: &str) -> Result<()> {
        let finite = |v: Vec3, what: &str| {
            if is_finite(v) {
                Ok(())
            } else {
                Err(Error::NotFinite {
                    what: format!("{name}: {what}"),
                })
            }
        };
        let direction = |v: Vec3, what: &str| {
            finite(v, what)?;
            if norm(v) == 0.0 {
                return Err(Error::ZeroNormal {
                    what: format!("{name}: {what}"),
                });
            }
            Ok(())
        };
        if let Some(at) = self.at() {
            check_point(surface, at, name)?;
        }
        match *self {
            Constraint::Point { target, .. } => finite(target, "target"),
            Constraint::Normal { normal, .. } => direction(normal, "normal"),
            Constraint::InPlane { normal, offset, .. } => {
                direction(normal, "normal")?;
                if offset.is_finite() {
                    Ok(())
                } else {
                    Err(Error::NotFinite {
                        what: format!("{name}: offset"),
                    })
                }
            }
            Constraint::OnLine {
                point,
                direction: d,
                ..
            } => {
                finite(point, "point")?;
                direction(d, "direction")
            }
            Constraint::Fixed { point, value } => {
                if point >= surface.point_count() {
                    return Err(Error::Mismatch {
                        what: format!("{name}: control point index"),
                        expected: format!("below {}", surface.point_count()),
                        got: point.to_string(),
                    });
                }
                finite(value, "value")
            }
        }
    }

    /// The domain point the constraint acts at (none for a fixed point).
    pub fn at(&self) -> Option<DomainPoint> {
        match *self {
            Constraint::Point { at, .. }
            | Constraint::Normal { at, .. }
            | Constraint::InPlane { at, .. }
            | Constraint::OnLine { at, .. } => Some(at),
            Constraint::Fixed { .. } => None,
        }
    }

    /// The same constraint at another domain point (after a refinement).
    pub fn moved_to(&self, to: DomainPoint) -> Constraint {
        let mut c = self.clone();
        match &mut c {
            Constraint::Point { at, .. }
            | Constraint::Normal { at, .. }
            | Constraint::InPlane { at, .. }
            | Constraint::OnLine { at, .. } => *at = to,
            Constraint::Fixed { .. } => {}
        }
        c
    }

    /// The constraint's equations over the surface's coordinates (none for
    /// a fixed point, which is eliminated instead). The constraint must
    /// have passed [`Constraint::validate`].
    pub fn rows(&self, surface: &TriSurface, name: &str) -> Vec<Row> {
        match *self {
            Constraint::Point { at, target } => {
                let w = point_weights(surface, at);
                (0..3)
                    .map(|c| Row {
                        terms: w.iter().map(|&(g, b)| (3 * g + c, b)).collect(),
                        rhs: target[c],
                        name: format!("{name}, {}", AXES[c]),
                    })
                    .collect()
            }
            Constraint::Normal { at, normal } => {
                let n = normalize(normal).expect("validated");
                [([1.0, 0.0, -1.0], "∂T/∂u"), ([0.0, 1.0, -1.0], "∂T/∂v")]
                    .iter()
                    .map(|&(d, which)| Row {
                        terms: vector_terms(&derivative_weights(surface, at, d), n),
                        rhs: 0.0,
                        name: format!("{name}, N·{which}"),
                    })
                    .collect()
            }
            Constraint::InPlane { at, normal, offset } => {
                let s = 1.0 / norm(normal);
                vec![Row {
                    terms: vector_terms(&point_weights(surface, at), scale(normal, s)),
                    rhs: offset * s,
                    name: name.to_string(),
                }]
            }
            Constraint::OnLine {
                at,
                point,
                direction,
            } => {
                let w = point_weights(surface, at);
                perpendiculars(direction)
                    .iter()
                    .enumerate()
                    .map(|(i, &a)| Row {
                        terms: vector_terms(&w, a),
                        rhs: dot(a, point),
                        name: format!("{name}, plane {}", i + 1),
                    })
                    .collect()
            }
            Constraint::Fixed { .. } => Vec::new(),
        }
    }

    /// How far the surface is from meeting the constraint, in its own
    /// terms: distance for point, plane and line constraints, the angle
    /// (radians) between the surface normal and the prescribed one (up to
    /// sign) for a normal constraint, and |P − value| for a fixed point.
    /// NaN where the surface normal is undefined.
    pub fn violation(&self, surface: &TriSurface) -> f64 {
        let value = |at: DomainPoint| surface.patch(at.triangle).eval(at.bary);
        match *self {
            Constraint::Point { at, target } => norm(sub(value(at), target)),
            Constraint::Normal { at, normal } => match surface.patch(at.triangle).normal(at.bary) {
                // Up to sign: the equations cannot tell N from −N.
                Some(n) => {
                    let a = angle(n, normal);
                    a.min(std::f64::consts::PI - a)
                }
                None => f64::NAN,
            },
            Constraint::InPlane { at, normal, offset } => {
                (dot(normal, value(at)) - offset).abs() / norm(normal)
            }
            Constraint::OnLine {
                at,
                point,
                direction,
            } => norm(cross(sub(value(at), point), direction)) / norm(direction),
            Constraint::Fixed { point, value } => norm(sub(surface.points()[point], value)),
        }
    }

    /// A short name of the kind, as in scene files.
    pub fn kind(&self) -> &'static str {
        match self {
            Constraint::Point { .. } => "point",
            Constraint::Normal { .. } => "normal",
            Constraint::InPlane { .. } => "in_plane",
            Constraint::OnLine { .. } => "on_line",
            Constraint::Fixed { .. } => "fixed",
        }
    }
}

/// (global point, B_J(p)) for the patch holding p.
fn point_weights(surface: &TriSurface, at: DomainPoint) -> Vec<(usize, f64)> {
    let g = surface.patch_indices(at.triangle);
    let b = tri_bernstein_all(surface.degree(), at.bary);
    g.iter()
        .copied()
        .zip(b)
        .filter(|&(_, w)| w != 0.0)
        .collect()
}

/// (global point, weight) with D_d T(p) = Σ weight · P_g for a direction d
/// (components summing to 0): n Σ_m d_m B^{n−1}_{J−e_m}(p).
pub(crate) fn derivative_weights(
    surface: &TriSurface,
    at: DomainPoint,
    d: Bary,
) -> Vec<(usize, f64)> {
    let n = surface.degree();
    let lower = tri_bernstein_all(n - 1, at.bary);
    let g = surface.patch_indices(at.triangle);
    multi_indices(n)
        .zip(g.iter().copied())
        .filter_map(|(j, gi)| {
            let w: f64 = (0..3)
                .filter(|&m| j[m] > 0)
                .map(|m| {
                    let mut l = j;
                    l[m] -= 1;
                    d[m] * lower[super::index::index_of(n - 1, l)]
                })
                .sum();
            (w != 0.0).then_some((gi, n as f64 * w))
        })
        .collect()
}

/// Terms of v · Σ w_g P_g over the coordinates.
fn vector_terms(weights: &[(usize, f64)], v: Vec3) -> Vec<(usize, f64)> {
    weights
        .iter()
        .flat_map(|&(g, w)| (0..3).map(move |c| (3 * g + c, w * v[c])))
        .filter(|&(_, a)| a != 0.0)
        .collect()
}

/// Two unit vectors perpendicular to d and to each other.
fn perpendiculars(d: Vec3) -> [Vec3; 2] {
    let d = normalize(d).expect("validated");
    let axis = if d[0].abs() <= d[1].abs() && d[0].abs() <= d[2].abs() {
        [1.0, 0.0, 0.0]
    } else if d[1].abs() <= d[2].abs() {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let a = normalize(cross(d, axis)).expect("axis not parallel to d");
    [a, cross(d, a)]
}
