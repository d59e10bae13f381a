//! The curved beam (CBEND): a circular arc of constant section between two grids, 12 DOFs
//! (T1 T2 T3 R1 R2 R3 of each end, basic system).
//!
//! # Arc
//! The arc runs from A to B on a circle of centre C, radius R and angle Θ, in the plane
//! spanned by the chord AB and the orientation vector v. Points on it are
//! p(φ) = C + R r(φ), r(φ) = cos φ e + sin φ (n × e), φ ∈ [0, Θ], with e the unit vector from
//! C to A and n the unit normal of the plane; the tangent is t(φ) = n × r(φ). [`ArcRule`] says
//! how C follows from A, B and v (MSC's CBEND GEOM 1–4 with PBEND RB or THETAB).
//!
//! # Stiffness: the force method
//! With end A clamped, a force F and moment M at B (basic) load the section at φ with the force
//! F and the moment M + (p_B − p(φ)) × F. In the section axes (t, r, n) these are the axial
//! force N, the in-plane shear V_r, the out-of-plane shear V_n, the torque T, the out-of-plane
//! bending moment M_r and the in-plane bending moment M_n: s(φ) = B(φ) [F; M]. The
//! complementary energy of the arc,
//! U* = ½ ∫ (N²/EA + V_r²/(K1 G A) + V_n²/(K2 G A) + T²/GJ + M_r²/(E I2) + M_n²/(E I1)) R dφ
//! = ½ [F; M]ᵀ 𝔽 [F; M], gives the flexibility 𝔽 = ∫ Bᵀ D B R dφ of end B (Castigliano's
//! theorem) and its stiffness K_BB = 𝔽⁻¹. A blank or zero K1/K2 drops that shear term (rigid
//! in shear). End B's displacement relative to A's rigid motion is
//! δ = u_B − [[I, −[c]×], [0, I]] u_A with c = p_B − p_A, so K = Sᵀ K_BB S with
//! S = [−[[I, −[c]×], [0, I]], I]; it has the six rigid-body modes exactly.
//!
//! This is the thin curved beam of classical strength of materials (the section small next to
//! R: the bending stress linear across the section, the neutral axis on the centroid) with
//! extension, shear and torsion, and exact for that model: one element reproduces the
//! Castigliano solutions of arcs (Roark's ring and arch cases) to round-off. MSC Nastran's
//! CBEND adds what paraflex refuses on the PBEND: the radial and normal centroid offsets RC, ZC,
//! the neutral-axis offset DELTAN of thick curved beams, and the pipe form with its
//! flexibility and stress-intensification factors (FSI). The integral is taken by 8-point
//! Gauss–Legendre on stretches of at most π/8: the integrand is a trigonometric polynomial of
//! degree 4 in φ, integrated to about 1e-15 relative.
//!
//! # Loads along the arc
//! [`grid_loads`]: the fixed-end reactions of a force or moment concentrated on the arc or
//! distributed linearly in arc length, by the same force method (exact for this model).
//!
//! # Mass
//! Lumped: half of (ρ A + NSM) R Θ on the translations of each end, no rotary inertia.
//!
//! # Affine parts (thesis eq. 3.12–3.14)
//! 𝔽 ∝ 1/E at a fixed G/E, so K ∝ E: one [`Coefficient::E`] part. E and G as separate
//! parameters are refused (K = 𝔽⁻¹ is not affine in them). The mass is ∝ ρ plus a constant
//! NSM part.

use super::affine::{AffineMatrix, Coefficient};
use super::beam::{Density, Elasticity};
use crate::geometry::quadrature::gauss_legendre;
use crate::geometry::vec3::{add, cross, dot, norm, scale, skew, sub};
use faer::Mat;
use faer::linalg::solvers::{DenseSolveCore, Solve};

/// How the arc follows from the ends A, B and the orientation vector v.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ArcRule {
    /// GEOM 1: the centre is on the line through A along v (or its extension); the shorter
    /// of the two arcs.
    CentreAlongV,
    /// GEOM 2: the tangent at A is along v, the arc on v's side of the chord AB.
    TangentAlongV,
    /// GEOM 3: this radius, the centre on the side of AB opposite to v (the shorter arc).
    Radius(f64),
    /// GEOM 4: this arc angle (radians, 0 < Θ < 2π), the centre on the side of AB opposite
    /// to v when Θ < π.
    Angle(f64),
}

/// Errors of the curved beam.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BendError {
    #[error("zero length: the end grids coincide")]
    ZeroLength,
    #[error(
        "the orientation vector is parallel to the chord AB (or zero): it cannot fix the plane of the arc"
    )]
    OrientationAlongChord,
    #[error(
        "GEOM = 1 with the orientation vector perpendicular to the chord AB puts the centre of curvature at infinity (a straight element: use a CBAR or CBEAM)"
    )]
    CentreAtInfinity,
    #[error("the bend radius RB = {radius:e} is less than half the chord AB ({half_chord:e})")]
    RadiusTooSmall { radius: f64, half_chord: f64 },
    #[error(
        "A, I1, I2 and J must be > 0 for the curved beam (A = {a:e}, I1 = {i1:e}, I2 = {i2:e}, J = {j:e})"
    )]
    SectionNotPositive { a: f64, i1: f64, i2: f64, j: f64 },
    #[error(
        "E and G as separate parameters do not give affine parts of a curved beam (its stiffness is the inverse of a flexibility); use an E parameter at fixed ν"
    )]
    SeparateModuli,
}

/// A circular arc from A (φ = 0) to B (φ = Θ) (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    pub centre: [f64; 3],
    pub radius: f64,
    /// Θ in radians, 0 < Θ < 2π.
    pub angle: f64,
    /// Unit vector from the centre to A.
    pub start: [f64; 3],
    /// Unit normal of the arc's plane; the arc turns positively about it from A to B.
    pub normal: [f64; 3],
}

impl Arc {
    /// The arc from `a` to `b` that `rule` describes with the orientation vector `v`.
    pub fn new(a: [f64; 3], b: [f64; 3], v: [f64; 3], rule: ArcRule) -> Result<Arc, BendError> {
        let chord = sub(b, a);
        let l = norm(chord);
        let size = norm(a).max(norm(b)).max(l);
        if !(l > 1e-12 * size) {
            return Err(BendError::ZeroLength);
        }
        let along = scale(chord, 1.0 / l);
        // v's component perpendicular to the chord: its side of AB
        let v_perp = sub(v, scale(along, dot(v, along)));
        if !(norm(v_perp) > 1e-8 * norm(v)) {
            return Err(BendError::OrientationAlongChord);
        }
        let side = scale(v_perp, 1.0 / norm(v_perp));
        let middle = scale(add(a, b), 0.5);
        // the centre, and the side of the chord the arc bulges to
        let (centre, bulge) = match rule {
            ArcRule::CentreAlongV => {
                let u = scale(v, 1.0 / norm(v));
                let across = dot(u, chord);
                if across.abs() <= 1e-8 * l {
                    return Err(BendError::CentreAtInfinity);
                }
                let centre = add(a, scale(u, l * l / (2.0 * across)));
                let bulge = if dot(sub(centre, middle), side) > 0.0 {
                    scale(side, -1.0)
                } else {
                    side
                };
                (centre, bulge)
            }
            ArcRule::TangentAlongV => {
                let u = scale(v, 1.0 / norm(v));
                let toward = sub(chord, scale(u, dot(chord, u)));
                let s = l * l / (2.0 * norm(toward));
                (add(a, scale(toward, s / norm(toward))), side)
            }
            ArcRule::Radius(r) => {
                if !(r >= 0.5 * l) {
                    return Err(BendError::RadiusTooSmall {
                        radius: r,
                        half_chord: 0.5 * l,
                    });
                }
                let h = (r * r - 0.25 * l * l).max(0.0).sqrt();
                (sub(middle, scale(side, h)), side)
            }
            ArcRule::Angle(theta) => {
                let r = 0.5 * l / (0.5 * theta).sin();
                (sub(middle, scale(side, r * (0.5 * theta).cos())), side)
            }
        };
        let to_a = sub(a, centre);
        let radius = norm(to_a);
        let start = scale(to_a, 1.0 / radius);
        // the apex C + R·bulge is reached from A by turning Θ/2 (< π) about n
        let turn = cross(start, bulge);
        let normal = scale(turn, 1.0 / norm(turn));
        let angle = 2.0 * norm(turn).atan2(dot(start, bulge));
        Ok(Arc {
            centre,
            radius,
            angle,
            start,
            normal,
        })
    }

    /// The unit radial vector r(φ) (from the centre outwards).
    fn radial(&self, phi: f64) -> [f64; 3] {
        add(
            scale(self.start, phi.cos()),
            scale(cross(self.normal, self.start), phi.sin()),
        )
    }

    /// The point p(φ) of the arc.
    pub fn point(&self, phi: f64) -> [f64; 3] {
        add(self.centre, scale(self.radial(phi), self.radius))
    }

    /// The arc length R Θ.
    pub fn length(&self) -> f64 {
        self.radius * self.angle
    }

    /// Gauss points (φ, weight in arc length) over [from, to] ⊂ [0, Θ], stretches ≤ π/8.
    pub fn quadrature(&self, from: f64, to: f64) -> Vec<(f64, f64)> {
        let pieces = ((to - from) / (std::f64::consts::PI / 8.0)).ceil().max(1.0) as usize;
        let h = (to - from) / pieces as f64;
        let mut out = Vec::with_capacity(8 * pieces);
        for k in 0..pieces {
            let mid = from + (k as f64 + 0.5) * h;
            for &(x, w) in gauss_legendre(8) {
                out.push((mid + 0.5 * h * x, 0.5 * h * w * self.radius));
            }
        }
        out
    }

    /// The section resultants (N, V_r, V_n, T, M_r, M_n) at φ of a unit force and moment
    /// (columns F1 F2 F3 M1 M2 M3, basic) applied at `at`, beyond the section.
    pub fn resultants(&self, phi: f64, at: [f64; 3]) -> [[f64; 6]; 6] {
        let r = self.radial(phi);
        let t = cross(self.normal, r);
        let axes = [t, r, self.normal];
        let lever = skew(sub(at, self.point(phi)));
        let mut b = [[0.0; 6]; 6];
        for (i, axis) in axes.iter().enumerate() {
            for j in 0..3 {
                b[i][j] = axis[j];
                b[3 + i][3 + j] = axis[j];
                // moment of the force about the section: (at − p) × F
                b[3 + i][j] = (0..3).map(|m| axis[m] * lever[m][j]).sum();
            }
        }
        b
    }
}

/// Section and moduli of a curved beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendSection {
    pub a: f64,
    /// In-plane bending inertia (PBEND I1) and out-of-plane (I2).
    pub i1: f64,
    pub i2: f64,
    pub j: f64,
    /// Shear area factors in and out of the plane (`None`: rigid in shear).
    pub k1: Option<f64>,
    pub k2: Option<f64>,
    pub nsm: f64,
}

impl BendSection {
    /// The compliances of (N, V_r, V_n, T, M_r, M_n) per unit length at moduli E, G.
    fn compliance(&self, e: f64, g: f64) -> [f64; 6] {
        let shear = |k: Option<f64>| k.map_or(0.0, |k| 1.0 / (k * g * self.a));
        [
            1.0 / (e * self.a),
            shear(self.k1),
            shear(self.k2),
            1.0 / (g * self.j),
            1.0 / (e * self.i2),
            1.0 / (e * self.i1),
        ]
    }

    fn check(&self) -> Result<(), BendError> {
        if [self.a, self.i1, self.i2, self.j].iter().all(|&x| x > 0.0) {
            Ok(())
        } else {
            Err(BendError::SectionNotPositive {
                a: self.a,
                i1: self.i1,
                i2: self.i2,
                j: self.j,
            })
        }
    }
}

/// The flexibility 𝔽 of end B with end A clamped (basic, rows and columns F1 F2 F3 M1 M2 M3).
pub fn tip_flexibility(arc: &Arc, s: &BendSection, e: f64, g: f64) -> Mat<f64> {
    let d = s.compliance(e, g);
    let tip = arc.point(arc.angle);
    let mut f = Mat::<f64>::zeros(6, 6);
    for (phi, w) in arc.quadrature(0.0, arc.angle) {
        let b = arc.resultants(phi, tip);
        for i in 0..6 {
            for j in 0..6 {
                f[(i, j)] += w * (0..6).map(|k| b[k][i] * d[k] * b[k][j]).sum::<f64>();
            }
        }
    }
    f
}

/// S: end B's displacement relative to A's rigid motion from the 12 element DOFs.
fn relative_motion(arc: &Arc) -> Mat<f64> {
    let c = skew(sub(arc.point(arc.angle), arc.point(0.0)));
    let mut s = Mat::<f64>::zeros(6, 12);
    for i in 0..6 {
        s[(i, i)] = -1.0;
        s[(i, 6 + i)] = 1.0;
    }
    for i in 0..3 {
        for j in 0..3 {
            s[(i, 3 + j)] = c[i][j];
        }
    }
    s
}

/// The Cholesky factor of the tip flexibility; a section that does not make it positive
/// definite is an error naming the section's values.
fn tip_flexibility_factor(
    arc: &Arc,
    s: &BendSection,
    e: f64,
    g: f64,
) -> Result<faer::linalg::solvers::Llt<f64>, BendError> {
    tip_flexibility(arc, s, e, g)
        .llt(faer::Side::Lower)
        .map_err(|_| BendError::SectionNotPositive {
            a: s.a,
            i1: s.i1,
            i2: s.i2,
            j: s.j,
        })
}

/// The 12×12 stiffness (basic) at moduli E, G.
pub fn stiffness(arc: &Arc, s: &BendSection, e: f64, g: f64) -> Result<Mat<f64>, BendError> {
    s.check()?;
    let kbb = tip_flexibility_factor(arc, s, e, g)?.inverse();
    let t = relative_motion(arc);
    Ok(t.transpose() * kbb * &t)
}

/// The stiffness split as `elasticity` says (see the module documentation).
pub fn affine_stiffness(
    arc: &Arc,
    s: &BendSection,
    elasticity: Elasticity,
) -> Result<AffineMatrix, BendError> {
    let part = match elasticity {
        Elasticity::Fixed { e, g } => (Coefficient::Constant, stiffness(arc, s, e, g)?),
        Elasticity::YoungsModulus { g_per_e } => (Coefficient::E, stiffness(arc, s, 1.0, g_per_e)?),
        Elasticity::Separate => return Err(BendError::SeparateModuli),
    };
    Ok(AffineMatrix { parts: vec![part] })
}

/// A load along the arc (`PLOAD1` on a CBEND): a force or moment in a fixed basic direction,
/// concentrated or distributed linearly in arc length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcLoad {
    /// True for a moment, false for a force.
    pub moment: bool,
    /// Unit direction (basic).
    pub direction: [f64; 3],
    /// Positions from A as fractions of the arc length, `at[0] ≤ at[1]`; equal: concentrated.
    pub at: [f64; 2],
    /// Intensities per unit arc length at the two positions; a concentrated load is
    /// `values[0]`.
    pub values: [f64; 2],
}

/// The grid loads (F1 F2 F3 M1 M2 M3 at A, then at B; basic) equivalent to `load`: minus the
/// reactions of the arc clamped at both ends, exact for the force-method element. With A
/// clamped and B free the load moves B by δ = Σ ∫₀^φₚ B_Bᵀ D B_p R dφ · P (Castigliano, P at
/// φₚ); clamping B takes K_BB δ, which is B's share, and A takes the rest of the load's force
/// and of its moment about A.
pub fn grid_loads(
    arc: &Arc,
    s: &BendSection,
    e: f64,
    g: f64,
    load: &ArcLoad,
) -> Result<[f64; 12], BendError> {
    s.check()?;
    let d = s.compliance(e, g);
    let (pa, pb) = (arc.point(0.0), arc.point(arc.angle));
    let [x1, x2] = load.at;
    // (φ, amount) of the concentrated load or of the Gauss points of the stretch
    let points: Vec<(f64, f64)> = if x2 > x1 {
        arc.quadrature(x1 * arc.angle, x2 * arc.angle)
            .into_iter()
            .map(|(phi, w)| {
                let t = (phi / arc.angle - x1) / (x2 - x1);
                (
                    phi,
                    w * (load.values[0] + t * (load.values[1] - load.values[0])),
                )
            })
            .collect()
    } else {
        vec![(x1 * arc.angle, load.values[0])]
    };
    let mut delta = [0.0; 6];
    let mut total = [0.0; 6];
    for (phi_p, amount) in points {
        let at = arc.point(phi_p);
        let mut p = [0.0; 6];
        let offset = if load.moment { 3 } else { 0 };
        p[offset..offset + 3].copy_from_slice(&scale(load.direction, amount));
        // the load's force and its moment about A
        let (force, moment) = ([p[0], p[1], p[2]], [p[3], p[4], p[5]]);
        let about_a = add(moment, cross(sub(at, pa), force));
        for k in 0..3 {
            total[k] += force[k];
            total[3 + k] += about_a[k];
        }
        for (phi, w) in arc.quadrature(0.0, phi_p) {
            let (bb, bp) = (arc.resultants(phi, pb), arc.resultants(phi, at));
            let sp: [f64; 6] = std::array::from_fn(|k| (0..6).map(|j| bp[k][j] * p[j]).sum());
            for (i, di) in delta.iter_mut().enumerate() {
                *di += w * (0..6).map(|k| bb[k][i] * d[k] * sp[k]).sum::<f64>();
            }
        }
    }
    let rhs = Mat::from_fn(6, 1, |i, _| delta[i]);
    let share = tip_flexibility_factor(arc, s, e, g)?.solve(&rhs);
    let at_b: [f64; 6] = std::array::from_fn(|i| share[(i, 0)]);
    let force_b = [at_b[0], at_b[1], at_b[2]];
    let moment_b_about_a = add([at_b[3], at_b[4], at_b[5]], cross(sub(pb, pa), force_b));
    let mut out = [0.0; 12];
    for k in 0..3 {
        out[k] = total[k] - force_b[k];
        out[3 + k] = total[3 + k] - moment_b_about_a[k];
    }
    out[6..].copy_from_slice(&at_b);
    Ok(out)
}

/// Lumped mass: half of `per_length` × R Θ on each end's translations.
fn lumped(arc: &Arc, per_length: f64) -> Mat<f64> {
    let half = 0.5 * per_length * arc.length();
    Mat::from_fn(12, 12, |i, j| if i == j && i % 6 < 3 { half } else { 0.0 })
}

/// The mass split as `density` says (see the module documentation).
pub fn affine_mass(arc: &Arc, s: &BendSection, density: Density) -> AffineMatrix {
    let parts = match density {
        Density::Fixed { rho } => vec![(Coefficient::Constant, lumped(arc, rho * s.a + s.nsm))],
        Density::Parameter => {
            let mut parts = vec![(Coefficient::Rho, lumped(arc, s.a))];
            if s.nsm != 0.0 {
                parts.push((Coefficient::Constant, lumped(arc, s.nsm)));
            }
            parts
        }
    };
    AffineMatrix { parts }
}

#[cfg(test)]
#[path = "bend_tests.rs"]
mod tests;
