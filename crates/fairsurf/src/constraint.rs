//! Linear constraints on a surface of any kind (Veltkamp & Wesselink §4 and
//! eq. 31, F P = G): point, normal, point-in-plane and point-on-line
//! interpolation at a point of the parameter domain, and fixed control
//! points. Written once against [`ConstraintSurface`]: a triangular surface
//! ([`crate::TriSurface`], at a [`crate::triangle::DomainPoint`]) and a
//! tensor-product patch ([`crate::TensorPatch`], at (u, v) ∈ [0, 1]²) differ
//! only in the weights that give a surface point and two tangents as
//! combinations of control points.
//!
//! Every constraint becomes rows over the 3N coordinates of the surface's N
//! control points, coordinate c of point g at index 3g + c:
//!
//! ```text
//! point     S(p) = P                  Σ_J B_J(p) P_J = P                      3 rows
//! normal    N·∂₁S = N·∂₂S = 0         eq. (8); ∂₁, ∂₂ two tangent directions  2 rows
//! in plane  n·S(p) = a                                                        1 row
//! on line   S(p) on {Q + s d}         a₁·S(p) = a₁·Q, a₂·S(p) = a₂·Q, a₁,a₂ ⊥ d  2 rows
//! fixed     P_g = value               eliminated before the solve             3 coordinates
//! ```

use crate::vec3::{angle, cross, dot, is_finite, norm, normalize, scale, sub, Vec3};
use crate::{Error, Result};

/// What a surface kind provides for its constraints: the surface point and
/// two tangent derivatives at a domain point as combinations Σ w_g P_g of
/// its control points, and the surface itself for the violations.
pub trait ConstraintSurface {
    /// A point of the parameter domain.
    type At: Copy + std::fmt::Debug + PartialEq;

    /// Checks that `at` is a point of the domain; the error names `what`.
    fn check_at(&self, at: Self::At, what: &str) -> Result<()>;
    /// (control point, B_g(at)): S(at) = Σ B_g P_g.
    fn point_weights(&self, at: Self::At) -> Vec<(usize, f64)>;
    /// Two independent tangent derivatives at `at` as weights over the
    /// control points, each with its name (e.g. `∂S/∂u`).
    fn tangent_weights(&self, at: Self::At) -> [(Vec<(usize, f64)>, &'static str); 2];
    /// S(at).
    fn value_at(&self, at: Self::At) -> Vec3;
    /// The unit normal at `at`, `None` where the surface is not regular.
    fn normal_at(&self, at: Self::At) -> Option<Vec3>;
    /// The control points.
    fn control_points(&self) -> &[Vec3];
}

/// Each constraint's violation on `surface` (as reports list them) and the
/// largest (0 without constraints).
pub(crate) fn outcomes<A, S>(
    constraints: &[NamedConstraint<A>],
    surface: &S,
) -> (Vec<ConstraintOutcome>, f64)
where
    A: Copy + std::fmt::Debug + PartialEq,
    S: ConstraintSurface<At = A>,
{
    let out: Vec<ConstraintOutcome> = constraints
        .iter()
        .map(|c| ConstraintOutcome {
            name: c.name.clone(),
            kind: c.constraint.kind(),
            violation: c.constraint.violation(surface),
        })
        .collect();
    let worst = out.iter().map(|c| c.violation).fold(0.0, f64::max);
    (out, worst)
}

/// Checks that (u, v) lies in the parameter rectangle `domain` up to 1e-12
/// of its size (rounding of a computed parameter); the error names `what`
/// and calls the rectangle `described`.
pub(crate) fn check_in_rectangle(
    at: [f64; 2],
    domain: [(f64, f64); 2],
    what: &str,
    described: impl FnOnce() -> String,
) -> Result<()> {
    let inside = at.iter().zip(domain).all(|(&t, (a, b))| {
        let slack = 1e-12 * (b - a).abs().max(1.0);
        t >= a - slack && t <= b + slack
    });
    if inside {
        return Ok(());
    }
    Err(Error::Mismatch {
        what: format!("{what}: (u, v)"),
        expected: described(),
        got: format!("{at:?}"),
    })
}

/// One linear constraint (eq. 31) at domain points of type `A`.
#[derive(Clone, Debug, PartialEq)]
pub enum Constraint<A> {
    /// The surface passes through `target` at `at`: S(at) = P (§4.1).
    Point {
        /// Where in the domain.
        at: A,
        /// The point to interpolate.
        target: Vec3,
    },
    /// The surface normal at `at` is `normal` (eq. 8: N·∂₁S = N·∂₂S = 0);
    /// up to sign, since the equations are linear.
    Normal {
        /// Where in the domain.
        at: A,
        /// The normal direction (any length but zero).
        normal: Vec3,
    },
    /// The surface point at `at` lies in the plane n·x = a (§4.1).
    InPlane {
        /// Where in the domain.
        at: A,
        /// The plane's normal n (any length but zero).
        normal: Vec3,
        /// Its offset a (with n as given).
        offset: f64,
    },
    /// The surface point at `at` lies on the line through `point` along
    /// `direction` (two point-in-plane constraints, §4.1).
    OnLine {
        /// Where in the domain.
        at: A,
        /// A point of the line.
        point: Vec3,
        /// Its direction (any length but zero).
        direction: Vec3,
    },
    /// The control point `point` keeps `value` (§6: eliminated from the
    /// minimization).
    Fixed {
        /// Control point index.
        point: usize,
        /// Its value.
        value: Vec3,
    },
}

/// A constraint with the name reports use (e.g. `constraints[2] (point)`).
#[derive(Clone, Debug, PartialEq)]
pub struct NamedConstraint<A> {
    /// How reports call it.
    pub name: String,
    /// What it requires.
    pub constraint: Constraint<A>,
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

/// One constraint's outcome on a result.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintOutcome {
    /// Its name.
    pub name: String,
    /// Its kind (`point`, `normal`, …, `curve`).
    pub kind: &'static str,
    /// [`Constraint::violation`] on the result (for a curve: the largest
    /// distance between the chain edges and the curve, sampled).
    pub violation: f64,
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl<A: Copy + std::fmt::Debug + PartialEq> Constraint<A> {
    /// Checks the constraint against the surface: its domain point, its
    /// vectors finite and not zero, a fixed point's index. The error names
    /// the constraint.
    pub fn validate<S: ConstraintSurface<At = A>>(&self, surface: &S, name: &str) -> Result<()> {
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
            surface.check_at(at, name)?;
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
                let count = surface.control_points().len();
                if point >= count {
                    return Err(Error::Mismatch {
                        what: format!("{name}: control point index"),
                        expected: format!("below {count}"),
                        got: point.to_string(),
                    });
                }
                finite(value, "value")
            }
        }
    }

    /// The domain point the constraint acts at (none for a fixed point).
    pub fn at(&self) -> Option<A> {
        match *self {
            Constraint::Point { at, .. }
            | Constraint::Normal { at, .. }
            | Constraint::InPlane { at, .. }
            | Constraint::OnLine { at, .. } => Some(at),
            Constraint::Fixed { .. } => None,
        }
    }

    /// The same constraint at another domain point (after a refinement).
    pub fn moved_to(&self, to: A) -> Constraint<A> {
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
    pub fn rows<S: ConstraintSurface<At = A>>(&self, surface: &S, name: &str) -> Vec<Row> {
        match *self {
            Constraint::Point { at, target } => {
                let w = surface.point_weights(at);
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
                surface
                    .tangent_weights(at)
                    .iter()
                    .map(|(w, which)| Row {
                        terms: vector_terms(w, n),
                        rhs: 0.0,
                        name: format!("{name}, N·{which}"),
                    })
                    .collect()
            }
            Constraint::InPlane { at, normal, offset } => {
                let s = 1.0 / norm(normal);
                vec![Row {
                    terms: vector_terms(&surface.point_weights(at), scale(normal, s)),
                    rhs: offset * s,
                    name: name.to_string(),
                }]
            }
            Constraint::OnLine {
                at,
                point,
                direction,
            } => {
                let w = surface.point_weights(at);
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
    pub fn violation<S: ConstraintSurface<At = A>>(&self, surface: &S) -> f64 {
        match *self {
            Constraint::Point { at, target } => norm(sub(surface.value_at(at), target)),
            Constraint::Normal { at, normal } => match surface.normal_at(at) {
                // Up to sign: the equations cannot tell N from −N.
                Some(n) => {
                    let a = angle(n, normal);
                    a.min(std::f64::consts::PI - a)
                }
                None => f64::NAN,
            },
            Constraint::InPlane { at, normal, offset } => {
                (dot(normal, surface.value_at(at)) - offset).abs() / norm(normal)
            }
            Constraint::OnLine {
                at,
                point,
                direction,
            } => norm(cross(sub(surface.value_at(at), point), direction)) / norm(direction),
            Constraint::Fixed { point, value } => norm(sub(surface.control_points()[point], value)),
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
