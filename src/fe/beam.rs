//! Two-node line elements: rods (CROD, CONROD, CTUBE: axial and torsion) and beams (CBAR,
//! CBEAM: axial, torsion and bending in two planes), 12 DOFs (T1 T2 T3 R1 R2 R3 of each end).
//!
//! # Element frame
//! The element axis runs between the two *offset points* A = GA + WA and B = GB + WB (offsets
//! in the basic system); x = (B − A)/L. For a beam, the orientation vector v (basic) fixes
//! plane 1 = the x–y plane: z = x × v / |x × v|, y = z × x. A rod has no bending, so any
//! y, z perpendicular to x serve. Local displacements u_l = Λ u_o with Λ = diag(R, R, R, R),
//! R's rows the element axes in basic; the offset points move rigidly with their grids:
//! u_o = u_g + θ_g × w = u_g − [w]× θ_g, so the element matrices are K_g = Tᵀ Λᵀ K_l Λ T with
//! T = diag([[I, −[w_A]×], [0, I]], [[I, −[w_B]×], [0, I]]).
//!
//! # Stiffness (element frame; local DOFs u, v, w, θx, θy, θz of A then B)
//! - axial E A / L and torsion G J / L;
//! - plane 1 (v, θz; bending about z with I1) and plane 2 (w, θy; I2): Timoshenko beam with
//!   the exact cubic/linear interpolation (Przemieniecki, *Theory of Matrix Structural
//!   Analysis*, §5.6): k = E I/(L³(1+Φ)) · [[12, 6L, −12, 6L], [6L, (4+Φ)L², −6L, (2−Φ)L²], …]
//!   with Φ = 12 E I/(K G A L²). K = `None` (Nastran's blank K1/K2 on PBAR; 0.0 on PBEAM) means
//!   no shear flexibility (Φ = 0: Euler–Bernoulli). Plane 2 is plane 1 with the signs of the
//!   rotations flipped (θy = −w′).
//! - product of inertia I12 = ∫yz dA (Euler–Bernoulli only): the bending energy
//!   ½ ∫ E (I1 v″² + 2 I12 v″ w″ + I2 w″²) dx couples the planes by E I12 ∫ N_v″ᵀ N_w″ dx;
//!   with shear flexibility it is refused ([`BeamError::ProductWithShear`]).
//! - neutral axis (PBEAM N1, N2) at (y_n, z_n) from the element axis: the axial and bending
//!   terms above act on the neutral axis, whose axial displacement is u + θy z_n − θz y_n
//!   (K_axis = Nᵀ K N); torsion and shear stay on the axis (the shear centre);
//! - pin flags (released end components in the element frame): static condensation
//!   K_cc − K_cr K_rr⁻¹ K_rc of each affine part separately. The parts act on disjoint DOF
//!   groups (axial + bending ∝ E, torsion ∝ G), so condensing each part is exact.
//!
//! # Mass (per length m = ρ A + NSM)
//! - lumped (Nastran's default, `PARAM,COUPMASS` ≠ 1): m L / 2 on the translations of each
//!   offset point, no rotary inertia;
//! - consistent: axial m L/6 [[2, 1], [1, 2]]; a rod's transverse translations the same
//!   (linear interpolation); a beam's bending the cubic Hermite matrix
//!   m L/420 [[156, 22L, 54, −13L], …] per plane; torsion ρ (I1 + I2) L/6 [[2, 1], [1, 2]]
//!   (NSM carries no rotary inertia).
//!
//! # Affine parts (thesis eq. 3.12–3.14, DESIGN.md §5)
//! [`Elasticity`] says how the stiffness splits: fixed (one constant part), ∝ E at a fixed G/E
//! ratio (every term, Timoshenko's Φ included, scales with E when G/E is fixed), or E and G
//! separately (axial and bending ∝ E, torsion ∝ G = μ; only without shear flexibility, since
//! E I/(1+Φ) with Φ ∝ E/G is not affine in (E, G)). The mass is ∝ ρ for A and I1 + I2 plus a
//! constant NSM part.

use super::affine::{AffineMatrix, Coefficient};
use crate::geometry::vec3::{add, cross, norm, normalize, skew, sub};
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

/// Section data of a line element.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LineSection {
    pub a: f64,
    /// Bending inertias (plane 1: about z, plane 2: about y) and product ∫yz dA.
    pub i1: f64,
    pub i2: f64,
    pub i12: f64,
    /// Torsion constant.
    pub j: f64,
    /// Shear area factors of planes 1 and 2 (`None`: rigid in shear).
    pub k1: Option<f64>,
    pub k2: Option<f64>,
    /// Non-structural mass per length.
    pub nsm: f64,
    /// Neutral axis (y, z) from the element axis (the shear centre), element frame.
    pub neutral_axis: [f64; 2],
}

/// Placement of a line element (basic system).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineGeometry {
    /// Grid locations of ends A and B.
    pub grids: [[f64; 3]; 2],
    /// Offsets WA, WB from the grids to the element ends.
    pub offsets: [[f64; 3]; 2],
    /// Orientation vector v of a beam (`None`: a rod, no bending).
    pub orientation: Option<[f64; 3]>,
}

/// Released components of each end (element frame, 0..6 = u v w θx θy θz).
pub type Releases = [[bool; 6]; 2];

/// How the stiffness splits into affine parts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Elasticity {
    /// One constant part with these moduli.
    Fixed { e: f64, g: f64 },
    /// One [`Coefficient::E`] part (the matrix at E = 1, G = `g_per_e`).
    YoungsModulus { g_per_e: f64 },
    /// A [`Coefficient::E`] part (axial, bending) and a [`Coefficient::Mu`] part (torsion).
    Separate,
}

/// How the mass splits into affine parts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Density {
    /// One constant part with this ρ.
    Fixed { rho: f64 },
    /// A [`Coefficient::Rho`] part (the matrix at ρ = 1 without NSM) and a constant NSM part.
    Parameter,
}

/// Errors of the line elements.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BeamError {
    #[error("zero length: the ends (grids plus offsets) coincide")]
    ZeroLength,
    #[error(
        "the orientation vector is parallel to the element axis (or zero): it cannot fix plane 1"
    )]
    OrientationAlongAxis,
    #[error("I1·I2 − I12² must be > 0 for bending (I1 = {i1:e}, I2 = {i2:e}, I12 = {i12:e})")]
    InertiaNotDefinite { i1: f64, i2: f64, i12: f64 },
    #[error(
        "I12 ≠ 0 with shear flexibility (K1/K2) is not supported; give I12 = 0 (principal axes) or no shear factors"
    )]
    ProductWithShear,
    #[error(
        "the pin flags leave a released component without stiffness (the element would be a mechanism)"
    )]
    PinMechanism,
    #[error(
        "E and G as separate parameters need no shear flexibility (E I/(1+Φ) is not affine in E and G); give K1/K2 blank or use an E parameter at fixed ν"
    )]
    SeparateModuliWithShear,
}

/// Local DOFs of plane 1 (v, θz at A then B) and plane 2 (w, θy).
const PLANE1: [usize; 4] = [1, 5, 7, 11];
const PLANE2: [usize; 4] = [2, 4, 8, 10];
/// θy = −w′: the plane-2 matrices are the plane-1 ones with these signs.
const PLANE2_SIGNS: [f64; 4] = [1.0, -1.0, 1.0, -1.0];

/// Element axes (rows of R: x, y, z in basic) and length.
fn frame(g: &LineGeometry) -> Result<([[f64; 3]; 3], f64), BeamError> {
    let a = add(g.grids[0], g.offsets[0]);
    let b = add(g.grids[1], g.offsets[1]);
    let d = sub(b, a);
    let l = norm(d);
    let scale = norm(g.grids[0]).max(norm(g.grids[1])).max(l);
    if !(l > 1e-12 * scale) {
        return Err(BeamError::ZeroLength);
    }
    let x = [d[0] / l, d[1] / l, d[2] / l];
    let v = match g.orientation {
        Some(v) => v,
        // a rod: any direction not along x
        None => {
            let k = (0..3)
                .min_by(|&i, &j| x[i].abs().total_cmp(&x[j].abs()))
                .unwrap_or(0);
            let mut e = [0.0; 3];
            e[k] = 1.0;
            e
        }
    };
    let zv = cross(x, v);
    if norm(zv) <= 1e-8 * norm(v) || norm(v) == 0.0 {
        return Err(BeamError::OrientationAlongAxis);
    }
    let z = normalize(zv).ok_or(BeamError::OrientationAlongAxis)?;
    let y = cross(z, x);
    Ok(([x, y, z], l))
}

/// The element length between the offset points (for mass properties).
pub fn length(g: &LineGeometry) -> Result<f64, BeamError> {
    frame(g).map(|(_, l)| l)
}

/// Bending stiffness of one plane (plane-1 signs) per unit E I, with shear parameter Φ.
fn bending(l: f64, phi: f64) -> [[f64; 4]; 4] {
    let c = 1.0 / (l.powi(3) * (1.0 + phi));
    let (l2, s) = (l * l, 6.0 * l);
    [
        [12.0, s, -12.0, s],
        [s, (4.0 + phi) * l2, -s, (2.0 - phi) * l2],
        [-12.0, -s, 12.0, -s],
        [s, (2.0 - phi) * l2, -s, (4.0 + phi) * l2],
    ]
    .map(|row| row.map(|v| v * c))
}

/// Φ = 12 E I/(K G A L²); 0 without shear flexibility.
fn shear_parameter(e: f64, g: f64, i: f64, k: Option<f64>, a: f64, l: f64) -> f64 {
    match k {
        Some(k) if k > 0.0 && i > 0.0 && g > 0.0 && a > 0.0 => 12.0 * e * i / (k * g * a * l * l),
        _ => 0.0,
    }
}

/// Local stiffness with moduli E, G (either may be 0 to isolate its terms).
fn local_stiffness(s: &LineSection, l: f64, e: f64, g: f64, ge: (f64, f64)) -> Mat<f64> {
    let mut k = Mat::<f64>::zeros(12, 12);
    let mut put = |i: usize, j: usize, v: f64| k[(i, j)] += v;
    for (i, j, sign) in [(0, 0, 1.0), (0, 6, -1.0), (6, 0, -1.0), (6, 6, 1.0)] {
        put(i, j, sign * e * s.a / l);
        put(i + 3, j + 3, sign * g * s.j / l);
    }
    // Φ uses the deck's moduli (ge), so a part evaluated at unit E keeps the element's Φ
    let phi1 = shear_parameter(ge.0, ge.1, s.i1, s.k1, s.a, l);
    let phi2 = shear_parameter(ge.0, ge.1, s.i2, s.k2, s.a, l);
    let b1 = bending(l, phi1);
    let b2 = bending(l, phi2);
    let b0 = bending(l, 0.0);
    for p in 0..4 {
        for q in 0..4 {
            let sign = PLANE2_SIGNS[p] * PLANE2_SIGNS[q];
            put(PLANE1[p], PLANE1[q], e * s.i1 * b1[p][q]);
            put(PLANE2[p], PLANE2[q], e * s.i2 * sign * b2[p][q]);
            let coupling = e * s.i12 * b0[p][q] * PLANE2_SIGNS[q];
            put(PLANE1[p], PLANE2[q], coupling);
            put(PLANE2[q], PLANE1[p], coupling);
        }
    }
    neutral_axis_offset(&k, s.neutral_axis)
}

/// K on the element axis from K on the neutral axis (y_n, z_n): the axial displacement there is
/// u + θy z_n − θz y_n at each end (a rigid section), everything else is the axis' own.
fn neutral_axis_offset(k: &Mat<f64>, [yn, zn]: [f64; 2]) -> Mat<f64> {
    if yn == 0.0 && zn == 0.0 {
        return k.clone();
    }
    let mut n = Mat::<f64>::identity(12, 12);
    for o in [0, 6] {
        n[(o, o + 4)] = zn;
        n[(o, o + 5)] = -yn;
    }
    n.transpose() * k * &n
}

/// Local mass with mass per length `m` and polar rotary inertia per length `ip`.
fn local_mass(m: f64, ip: f64, l: f64, form: MassForm, rod: bool) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(12, 12);
    if let MassForm::Lumped { torsion } = form {
        for i in [0, 1, 2, 6, 7, 8] {
            out[(i, i)] = m * l / 2.0;
        }
        if torsion {
            out[(3, 3)] = ip * l / 2.0;
            out[(9, 9)] = ip * l / 2.0;
        }
        return out;
    }
    let linear = [[2.0, 1.0], [1.0, 2.0]];
    let translations: &[usize] = if rod { &[0, 1, 2] } else { &[0] };
    for (p, row) in linear.iter().enumerate() {
        for (q, v) in row.iter().enumerate() {
            for &c in translations {
                out[(c + 6 * p, c + 6 * q)] += m * l / 6.0 * v;
            }
            out[(3 + 6 * p, 3 + 6 * q)] += ip * l / 6.0 * v;
        }
    }
    if !rod {
        let h = [
            [156.0, 22.0 * l, 54.0, -13.0 * l],
            [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
            [54.0, 13.0 * l, 156.0, -22.0 * l],
            [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
        ];
        for p in 0..4 {
            for q in 0..4 {
                let v = m * l / 420.0 * h[p][q];
                out[(PLANE1[p], PLANE1[q])] += v;
                out[(PLANE2[p], PLANE2[q])] += PLANE2_SIGNS[p] * PLANE2_SIGNS[q] * v;
            }
        }
    }
    out
}

/// Static condensation of the released DOFs (kept rows/columns keep their places, released
/// ones become zero). Released DOFs the part does not touch are left alone.
fn condense(k: &Mat<f64>, released: &[usize]) -> Result<Mat<f64>, BeamError> {
    let scale = (0..12).map(|i| k[(i, i)].abs()).fold(0.0, f64::max);
    let r: Vec<usize> = released
        .iter()
        .copied()
        .filter(|&i| (0..12).any(|j| k[(i, j)] != 0.0))
        .collect();
    if r.is_empty() {
        return Ok(k.clone());
    }
    let krr = Mat::from_fn(r.len(), r.len(), |p, q| k[(r[p], r[q])]);
    if (0..r.len()).any(|p| krr[(p, p)] <= 1e-12 * scale) {
        return Err(BeamError::PinMechanism);
    }
    let llt = krr.llt(Side::Lower).map_err(|_| BeamError::PinMechanism)?;
    let mut x = Mat::from_fn(r.len(), 12, |p, j| k[(r[p], j)]);
    llt.solve_in_place(x.as_mut());
    let mut out = Mat::from_fn(12, 12, |i, j| {
        k[(i, j)] - (0..r.len()).map(|p| k[(i, r[p])] * x[(p, j)]).sum::<f64>()
    });
    // a released row/column is exactly zero after condensation
    for &i in &r {
        for j in 0..12 {
            out[(i, j)] = 0.0;
            out[(j, i)] = 0.0;
        }
    }
    Ok(out)
}

/// Λ T: local element DOFs from the grids' basic DOFs.
fn transformation(g: &LineGeometry, axes: &[[f64; 3]; 3]) -> Mat<f64> {
    let mut t = Mat::<f64>::zeros(12, 12);
    for end in 0..2 {
        let w = skew(g.offsets[end]);
        let o = 6 * end;
        for i in 0..3 {
            for j in 0..3 {
                t[(o + i, o + j)] = axes[i][j];
                t[(o + 3 + i, o + 3 + j)] = axes[i][j];
                // u_o = u_g − [w]× θ_g, rotated
                let r_w: f64 = (0..3).map(|m| axes[i][m] * w[m][j]).sum();
                t[(o + i, o + 3 + j)] = -r_w;
            }
        }
    }
    t
}

fn to_grids(local: &Mat<f64>, t: &Mat<f64>) -> Mat<f64> {
    t.transpose() * local * t
}

/// Stiffness of a line element split as `elasticity` says, pins released (see module doc).
pub fn affine_stiffness(
    g: &LineGeometry,
    s: &LineSection,
    elasticity: Elasticity,
    releases: &Releases,
    moduli: (f64, f64),
) -> Result<AffineMatrix, BeamError> {
    let (axes, l) = frame(g)?;
    let mut s = *s;
    if g.orientation.is_none() {
        s = LineSection {
            i1: 0.0,
            i2: 0.0,
            i12: 0.0,
            k1: None,
            k2: None,
            ..s
        };
    }
    let bends = s.i1 != 0.0 || s.i2 != 0.0 || s.i12 != 0.0;
    if bends && s.i1 * s.i2 - s.i12 * s.i12 <= 0.0 {
        return Err(BeamError::InertiaNotDefinite {
            i1: s.i1,
            i2: s.i2,
            i12: s.i12,
        });
    }
    let shear = s.k1.is_some_and(|k| k > 0.0) || s.k2.is_some_and(|k| k > 0.0);
    if s.i12 != 0.0 && shear {
        return Err(BeamError::ProductWithShear);
    }
    let parts = match elasticity {
        Elasticity::Fixed { e, g } => {
            vec![(Coefficient::Constant, local_stiffness(&s, l, e, g, (e, g)))]
        }
        Elasticity::YoungsModulus { g_per_e } => {
            vec![(Coefficient::E, local_stiffness(&s, l, 1.0, g_per_e, moduli))]
        }
        Elasticity::Separate => {
            if shear {
                return Err(BeamError::SeparateModuliWithShear);
            }
            vec![
                (Coefficient::E, local_stiffness(&s, l, 1.0, 0.0, moduli)),
                (Coefficient::Mu, local_stiffness(&s, l, 0.0, 1.0, moduli)),
            ]
        }
    };
    let released: Vec<usize> = (0..12).filter(|&i| releases[i / 6][i % 6]).collect();
    let t = transformation(g, &axes);
    let parts = parts
        .into_iter()
        .map(|(c, k)| Ok((c, to_grids(&condense(&k, &released)?, &t))))
        .collect::<Result<Vec<_>, BeamError>>()?;
    Ok(AffineMatrix { parts })
}

/// Consistent or lumped mass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MassForm {
    /// Linear axial and torsional, cubic Hermite bending (and, for rods, linear transverse).
    Coupled,
    /// m L/2 on each end's translations; with `torsion`, also ρ(I1 + I2)L/2 on each end's
    /// twist, as Nastran lumps a CBEAM (a CBAR's lumped mass has none).
    Lumped { torsion: bool },
}

/// Mass of a line element split as `density` says (see module doc).
pub fn affine_mass(
    g: &LineGeometry,
    s: &LineSection,
    density: Density,
    form: MassForm,
) -> Result<AffineMatrix, BeamError> {
    let (axes, l) = frame(g)?;
    let rod = g.orientation.is_none();
    let polar = if rod { 0.0 } else { s.i1 + s.i2 };
    let t = transformation(g, &axes);
    let at = |m: f64, ip: f64| to_grids(&local_mass(m, ip, l, form, rod), &t);
    let parts = match density {
        Density::Fixed { rho } => vec![(Coefficient::Constant, at(rho * s.a + s.nsm, rho * polar))],
        Density::Parameter => {
            let mut parts = vec![(Coefficient::Rho, at(s.a, polar))];
            if s.nsm != 0.0 {
                parts.push((Coefficient::Constant, at(s.nsm, 0.0)));
            }
            parts
        }
    };
    Ok(AffineMatrix { parts })
}

/// The element axes (rows: x, y, z in basic) of a line element.
pub fn element_axes(g: &LineGeometry) -> Result<[[f64; 3]; 3], BeamError> {
    frame(g).map(|(axes, _)| axes)
}
