//! Shell section stiffness and mass by classical lamination theory (thesis §2.2.3, eq. 2.7–2.9;
//! affine splits §3.3, eq. 3.13–3.22; DESIGN.md §4–§5).
//!
//! A [`ShellSection`] holds the stress resultants of the reference plane (the grid plane of the
//! element) per unit generalized strain:
//!
//! ```text
//! ⎡N⎤   ⎡A B 0⎤ ⎡ε⁰⎤      N = [Nx Ny Nxy], M = [Mx My Mxy] (per unit length)
//! ⎢M⎥ = ⎢B D 0⎥ ⎢κ ⎥      ε⁰ = [εx εy γxy] of the reference plane, κ = [κx κy κxy]
//! ⎣Q⎦   ⎣0 0 S⎦ ⎣γ ⎦      Q = [Qxz Qyz], γ = [γxz γyz]
//! ```
//!
//! with, for plies k of reduced stiffness Q̄_k between z_k and z_{k+1} (z along the element
//! normal, measured from the reference plane):
//!
//! ```text
//! A = Σ Q̄_k (z_{k+1} − z_k),   B = ½ Σ Q̄_k (z_{k+1}² − z_k²),   D = ⅓ Σ Q̄_k (z_{k+1}³ − z_k³)
//! S = 5/6 Σ Q̄s_k (z_{k+1} − z_k)
//! ```
//!
//! This is eq. 2.9 of the thesis; note that its printed factors ½ and ⅓ are attached to the
//! bending and coupling terms the other way round — the line above is the standard CLT result
//! (B is the first moment, D the second), which the tests check against hand calculations.
//!
//! **Transverse shear.** S uses the shear-correction factor 5/6 on the thickness-weighted
//! rotated ply shear moduli (Q̄s = Rᵀ diag(G1Z, G2Z) R). The energy-consistent factors of a
//! general laminate depend non-linearly on the ply properties and angles; the simple factor
//! keeps S affine in every parameter of §5 (DESIGN.md), which is why it is used.
//!
//! **Drilling stiffness.** `drill = DRILL_FRACTION · A66` = A66 (Hughes–Brezzi penalty modulus
//! γ = G·t, per unit area, the full strength Ibrahimbegovic, Taylor & Wilson (1990) use with
//! their drilling membrane; see [`crate::fe::shell`], which weakens it for the CTRIA3). Being a
//! fixed multiple of A66 it is affine in every parameter A66 is.
//!
//! **PSHELL.** A homogeneous PSHELL is not a laminate: Nastran gives each of membrane (MID1),
//! bending (MID2 with 12I/T³), transverse shear (MID3 with TS/T) and membrane–bending coupling
//! (MID4) its own material, A = T·Q1, B = T²·Q4, D = (12I/T³)·T³/12·Q2, S = (TS/T)·T·G3
//! ([`PshellSection`]). The PSHELL shear factor is the card's TS/T (default 0.833333), not the
//! laminate's 5/6.
//!
//! **Kirchhoff sections.** A PSHELL with MID2 but without MID3 (or a ply without G1Z/G2Z) means
//! "no transverse-shear flexibility" (Nastran: rigid in transverse shear). The element is
//! Mindlin–Reissner, so this is represented by a stiff penalty: S = [`KIRCHHOFF_SHEAR_PENALTY`]
//! · (12I/T³) · G · T for a PSHELL (G the in-plane shear modulus of MID2), the modulus
//! `KIRCHHOFF_SHEAR_PENALTY` · G12 for a ply. Against the bending stiffness D ~ (12I/T³)·E·T³/12
//! of an element of size L the shear flexibility is then ~ 1/(100·(L/T)²·12G/E) of the bending
//! one, whatever 12I/T³; MITC elements do not lock, so the penalty costs nothing but a little
//! conditioning (at most 100/(TS/T) ≈ 120 times the shear stiffness of the same section with
//! MID3 given). The penalty is linear in the MID2 constants, so it splits with them.
//!
//! **Mass.** [`ShellMass`] holds ∫ρ dz (+ NSM), ∫ρ z dz and ∫ρ z² dz about the reference plane.

use super::affine::{Coefficient, CoefficientValues};

/// Drilling penalty modulus as a fraction of the in-plane shear stiffness A66.
pub const DRILL_FRACTION: f64 = 1.0;

/// Transverse shear stiffness of a Kirchhoff (no MID3 / no G1Z, G2Z) section, as a multiple
/// of G·t.
pub const KIRCHHOFF_SHEAR_PENALTY: f64 = 1.0e2;

/// Mass per unit reference area of a shell section (about the reference plane).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ShellMass {
    /// Translational mass per area, ∫ρ dz + NSM.
    pub rho_t: f64,
    /// First moment per area, ∫ρ z dz (non-zero for offset sections; couples translation and
    /// rotation).
    pub rho_s: f64,
    /// Rotary inertia per area about the reference plane, ∫ρ z² dz = Σ ρ_k (z_{k+1}³ − z_k³)/3.
    pub rho_i: f64,
}

/// Stress-resultant stiffness and mass of a shell section (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ShellSection {
    /// Membrane stiffness A (force/length), order [xx, yy, xy].
    pub a: [[f64; 3]; 3],
    /// Membrane–bending coupling B (force).
    pub b: [[f64; 3]; 3],
    /// Bending stiffness D (force·length).
    pub d: [[f64; 3]; 3],
    /// Transverse-shear stiffness S (force/length), order [xz, yz].
    pub s: [[f64; 2]; 2],
    /// Drilling penalty modulus γ per unit area (force/length), `DRILL_FRACTION · A66`.
    pub drill: f64,
    /// Mass per unit area.
    pub mass: ShellMass,
}

/// Plane-stress material of one PSHELL role, in the element material axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ShellMaterial {
    /// MAT1: plane-stress Q = E/(1−ν²)[[1,ν,0],[ν,1,0],[0,0,(1−ν)/2]]; transverse shear
    /// G = E/(2(1+ν)) in both directions.
    Isotropic {
        /// Young's modulus E.
        e: f64,
        /// Poisson's ratio ν.
        nu: f64,
    },
    /// MAT8: Q of [`Ply`] in its own axes (1 = material x); transverse shear diag(G1Z, G2Z),
    /// a blank modulus meaning rigid (penalty `KIRCHHOFF_SHEAR_PENALTY · G12`).
    Orthotropic {
        /// Modulus along material x.
        e1: f64,
        /// Modulus along material y.
        e2: f64,
        /// Major Poisson's ratio ν12.
        nu12: f64,
        /// In-plane shear modulus G12.
        g12: f64,
        /// Transverse shear modulus G1Z; `None` = rigid.
        g1z: Option<f64>,
        /// Transverse shear modulus G2Z; `None` = rigid.
        g2z: Option<f64>,
    },
    /// MAT2: the plane-stress matrix Q = G (symmetric, order xx, yy, xy) taken as given; as
    /// MID3 its [[G11, G12], [G12, G22]] is the transverse-shear matrix of (xz, yz) and G13,
    /// G23, G33 must be 0 (MSC/NX Quick Reference Guide, MAT2).
    Anisotropic {
        /// G11 … G33.
        g: [[f64; 3]; 3],
    },
}

/// The material of one PSHELL role (MID1 … MID4): its card id, constants and density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoleMaterial {
    /// Material id (MAT1 / MAT8), which PMPAR parameters refer to.
    pub mid: u32,
    /// Elastic constants.
    pub material: ShellMaterial,
    /// Density (used only by the mass role: MID1, or MID2 when MID1 is blank).
    pub rho: f64,
}

/// PSHELL section with Nastran's roles (MSC/NX Quick Reference Guide, PSHELL):
///
/// ```text
/// A = T·Q1          B = T²·Q4          D = (12I/T³)·T³/12·Q2          S = (TS/T)·T·G3
/// ```
///
/// with Q1, Q2, Q4 the plane-stress matrices of MID1 (membrane), MID2 (bending), MID4
/// (membrane–bending coupling) and G3 the transverse-shear matrix of MID3 (MAT1: G·I, MAT8:
/// diag(G1Z, G2Z)). A blank role contributes nothing, except:
/// - MID2 blank: membrane only (no B, D, S); MID3 and MID4 must then be blank;
/// - MID3 blank with MID2 given: rigid in transverse shear, represented by the stiff penalty
///   S = `KIRCHHOFF_SHEAR_PENALTY` · (12I/T³) · G2 · T · I₂ with G2 the in-plane shear modulus
///   of MID2 (module documentation; the factor 12I/T³ keeps the penalty-to-bending ratio
///   independent of it).
///
/// The reference plane lies ZOFFS below the mid-surface (z₀ = `zoffs`, the rigid offset of
/// Nastran's ZOFFS): ε_mid = ε + z₀κ, M_ref = M_mid + z₀N give
/// B_ref = B + z₀A and D_ref = D + 2z₀B + z₀²A. Nastran requires MID1 and MID2 for an offset.
///
/// Mass (Nastran: "from the density using the membrane thickness and membrane material"):
/// ρT + NSM, ρT·z₀ and ρ(T³/12 + T·z₀²) per area, ρ of MID1 (of MID2 when MID1 is blank).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PshellSection {
    /// Membrane thickness T.
    pub t: f64,
    /// MID1.
    pub membrane: Option<RoleMaterial>,
    /// MID2.
    pub bending: Option<RoleMaterial>,
    /// 12I/T³ (used with MID2).
    pub bending_ratio: f64,
    /// MID3.
    pub shear: Option<RoleMaterial>,
    /// TS/T (used with MID3).
    pub shear_ratio: f64,
    /// MID4.
    pub coupling: Option<RoleMaterial>,
    /// Non-structural mass per area.
    pub nsm: f64,
    /// Offset of the mid-surface from the reference (grid) plane along the normal (ZOFFS).
    pub zoffs: f64,
}

/// One orthotropic ply (MAT8 data, thickness and angle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ply {
    /// Modulus along the fibres.
    pub e1: f64,
    /// Modulus across the fibres.
    pub e2: f64,
    /// Major Poisson's ratio ν12.
    pub nu12: f64,
    /// In-plane shear modulus G12.
    pub g12: f64,
    /// Transverse shear modulus G1Z (fibre–normal plane); `None` = rigid in transverse shear
    /// (penalty `KIRCHHOFF_SHEAR_PENALTY · G12`).
    pub g1z: Option<f64>,
    /// Transverse shear modulus G2Z; `None` as for `g1z`.
    pub g2z: Option<f64>,
    /// Density.
    pub rho: f64,
    /// Thickness.
    pub t: f64,
    /// Fibre angle Θ in degrees from the material x axis, about the element normal.
    pub theta_deg: f64,
}

/// A laminate (PCOMP): plies from bottom to top.
#[derive(Debug, Clone, PartialEq)]
pub struct Laminate {
    /// Plies, bottom (most negative z) first.
    pub plies: Vec<Ply>,
    /// Distance from the reference plane to the bottom surface (Z0); `None` = −h/2.
    pub z0: Option<f64>,
    /// Non-structural mass per area.
    pub nsm: f64,
    /// LAM = SYM: `plies` is the bottom half; the full stack is `plies` followed by its mirror.
    pub symmetric: bool,
}

/// Section data an element property can carry. Held once per property (elements refer to it),
/// so the laminate variant's size is not worth a box.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum SectionData {
    /// PSHELL; the E, NU and RHO parameters act on the material `parametrized` (a material
    /// id): every role using it is split, the other roles go to the constant part.
    Pshell {
        /// The section.
        section: PshellSection,
        /// Material id the parameter refers to (PMPAR REFID).
        parametrized: u32,
    },
    /// PCOMP.
    Laminate(Laminate),
}

/// The parameter a section is split by in [`affine_sections`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SectionParameter {
    /// Young's modulus at fixed ν (isotropic): stiffness ∝ E (eq. 3.15).
    E,
    /// Poisson's ratio (isotropic): λ* = Eν/(1−ν²) and μ parts (eq. 3.13–3.14, plane stress).
    Nu,
    /// Density: mass ∝ ρ, NSM constant (eq. 3.16). Laminates need one density for all plies.
    Rho,
    /// Angle-ply angle Θ: every ply at sign(θ_k)·Θ (θ_k ≥ 0 → +Θ), eq. 3.17–3.18.
    Theta,
    /// Common ply thickness h: h, h², h³ (eq. 3.19–3.22). All plies must have equal thickness;
    /// Z0 is taken proportional to h (exact for the default Z0 = −h_total/2).
    Tply,
}

/// Errors of section construction and affine splitting.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SectionError {
    /// A quantity that must be positive is not.
    #[error("{what} must be positive, got {value}")]
    NonPositive {
        /// Name of the quantity, e.g. "thickness T" or "ply 3 thickness".
        what: String,
        /// The value given.
        value: f64,
    },
    /// Poisson's ratio outside (−1, 0.5) (isotropic) or making the ply compliance indefinite.
    #[error("{what}: Poisson's ratio {value} makes the material indefinite")]
    Poisson {
        /// Which material, e.g. "MAT1" or "ply 2".
        what: String,
        /// The ratio.
        value: f64,
    },
    /// A laminate without plies.
    #[error("laminate has no plies")]
    NoPlies,
    /// A PSHELL role combination Nastran does not allow (e.g. MID3 without MID2).
    #[error("PSHELL: {0}")]
    Roles(String),
    /// The parameter does not apply to this kind of section.
    #[error("parameter {parameter:?} does not apply to a {section} section")]
    UnsupportedParameter {
        /// The parameter asked for.
        parameter: SectionParameter,
        /// "PSHELL", "MAT8 PSHELL" or "laminate".
        section: &'static str,
    },
    /// TPLY needs all plies of one thickness, RHO one density.
    #[error(
        "parameter {parameter:?} needs equal {what} in all plies: ply 1 has {first}, ply {ply} has {value}"
    )]
    NotUniform {
        /// The parameter asked for.
        parameter: SectionParameter,
        /// "thickness" or "density".
        what: &'static str,
        /// Value of the first ply.
        first: f64,
        /// 1-based index of the first differing ply.
        ply: usize,
        /// Its value.
        value: f64,
    },
}

type M3 = [[f64; 3]; 3];
type M2 = [[f64; 2]; 2];

fn m3_scale(m: &M3, f: f64) -> M3 {
    m.map(|r| r.map(|x| x * f))
}

fn m3_add(a: &M3, b: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][j] + b[i][j]))
}

fn m2_scale(m: &M2, f: f64) -> M2 {
    m.map(|r| r.map(|x| x * f))
}

fn m2_add(a: &M2, b: &M2) -> M2 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][j] + b[i][j]))
}

impl ShellMass {
    /// `f · self`.
    pub fn scaled(&self, f: f64) -> Self {
        Self {
            rho_t: f * self.rho_t,
            rho_s: f * self.rho_s,
            rho_i: f * self.rho_i,
        }
    }

    /// `self + other`.
    pub fn plus(&self, o: &Self) -> Self {
        Self {
            rho_t: self.rho_t + o.rho_t,
            rho_s: self.rho_s + o.rho_s,
            rho_i: self.rho_i + o.rho_i,
        }
    }

    /// True when every entry is zero.
    pub fn is_zero(&self) -> bool {
        *self == Self::default()
    }
}

impl ShellSection {
    /// `f · self` (stiffness and mass).
    pub fn scaled(&self, f: f64) -> Self {
        Self {
            a: m3_scale(&self.a, f),
            b: m3_scale(&self.b, f),
            d: m3_scale(&self.d, f),
            s: m2_scale(&self.s, f),
            drill: f * self.drill,
            mass: self.mass.scaled(f),
        }
    }

    /// `self + other` (stiffness and mass).
    pub fn plus(&self, o: &Self) -> Self {
        Self {
            a: m3_add(&self.a, &o.a),
            b: m3_add(&self.b, &o.b),
            d: m3_add(&self.d, &o.d),
            s: m2_add(&self.s, &o.s),
            drill: self.drill + o.drill,
            mass: self.mass.plus(&o.mass),
        }
    }

    /// True when all stiffness entries (A, B, D, S, drill) are zero.
    pub fn stiffness_is_zero(&self) -> bool {
        let z = Self {
            mass: ShellMass::default(),
            ..*self
        };
        z == Self::default()
    }

    /// The same section without its mass.
    pub fn without_mass(&self) -> Self {
        Self {
            mass: ShellMass::default(),
            ..*self
        }
    }

    /// The mass only (zero stiffness).
    pub fn mass_only(mass: ShellMass) -> Self {
        Self {
            mass,
            ..Self::default()
        }
    }

    /// PSHELL section ([`PshellSection`]): stiffness and mass.
    pub fn pshell(p: &PshellSection) -> Result<Self, SectionError> {
        validate_pshell(p)?;
        let mut s = pshell_stiffness(p, |m| role_matrices(&m.material));
        s.mass = pshell_mass(p, mass_material(p)?.rho);
        Ok(s)
    }

    /// Laminate section by CLT (eq. 2.8–2.9, module documentation). Ply stiffness is rotated
    /// as Q̄ = T_εᵀ Q T_ε with the engineering-strain rotation T_ε(Θ).
    pub fn laminate(l: &Laminate) -> Result<Self, SectionError> {
        let plies = expand_plies(l)?;
        let z = ply_interfaces(&plies, l.z0);
        let mut out = Self::default();
        for (k, p) in plies.iter().enumerate() {
            let (z1, z2) = (z[k], z[k + 1]);
            let q = qbar_rotated(&ply_q(p), p.theta_deg);
            let g = qbar_shear_rotated(p, p.theta_deg);
            out.a = m3_add(&out.a, &m3_scale(&q, z2 - z1));
            out.b = m3_add(&out.b, &m3_scale(&q, 0.5 * (z2 * z2 - z1 * z1)));
            out.d = m3_add(&out.d, &m3_scale(&q, (z2.powi(3) - z1.powi(3)) / 3.0));
            out.s = m2_add(&out.s, &m2_scale(&g, SHEAR_CORRECTION * (z2 - z1)));
            out.mass = out.mass.plus(&ply_mass(p.rho, z1, z2));
        }
        out.mass.rho_t += l.nsm;
        out.drill = DRILL_FRACTION * out.a[2][2];
        Ok(out)
    }
}

/// Shear-correction factor on the thickness-weighted transverse shear moduli.
const SHEAR_CORRECTION: f64 = 5.0 / 6.0;

fn validate_pshell(p: &PshellSection) -> Result<(), SectionError> {
    positive("thickness T", p.t)?;
    let roles = [
        ("MID1", p.membrane),
        ("MID2", p.bending),
        ("MID3", p.shear),
        ("MID4", p.coupling),
    ];
    for (name, role) in roles {
        if let Some(m) = role {
            validate_material(&format!("{name} = {}", m.mid), name, &m.material)?;
        }
    }
    let rule = |ok: bool, what: &str| {
        if ok {
            Ok(())
        } else {
            Err(SectionError::Roles(what.to_string()))
        }
    };
    mass_material(p)?;
    rule(
        p.shear.is_none() || p.bending.is_some(),
        "MID3 must be blank unless MID2 is given",
    )?;
    rule(
        p.coupling.is_none() || (p.membrane.is_some() && p.bending.is_some()),
        "MID4 must be blank unless MID1 and MID2 are given",
    )?;
    rule(
        p.zoffs == 0.0 || (p.membrane.is_some() && p.bending.is_some()),
        "an offset (ZOFFS) needs MID1 and MID2",
    )?;
    if p.bending.is_some() {
        positive("bending ratio 12I/T³", p.bending_ratio)?;
    }
    if p.shear.is_some() {
        positive("shear ratio TS/T", p.shear_ratio)?;
    }
    Ok(())
}

/// The constants of the material of PSHELL role `role` (`MID1` … `MID4`).
fn validate_material(what: &str, role: &str, m: &ShellMaterial) -> Result<(), SectionError> {
    match *m {
        ShellMaterial::Isotropic { e, nu } => {
            positive(&format!("{what}: Young's modulus E"), e)?;
            if !(nu > -1.0 && nu < 0.5) {
                return Err(SectionError::Poisson {
                    what: what.to_string(),
                    value: nu,
                });
            }
        }
        ShellMaterial::Anisotropic { g } => validate_anisotropic(what, role, &g)?,
        ShellMaterial::Orthotropic {
            e1,
            e2,
            nu12,
            g12,
            g1z,
            g2z,
        } => {
            positive(&format!("{what}: E1"), e1)?;
            positive(&format!("{what}: E2"), e2)?;
            positive(&format!("{what}: G12"), g12)?;
            for (name, g) in [("G1Z", g1z), ("G2Z", g2z)] {
                if let Some(g) = g {
                    positive(&format!("{what}: {name}"), g)?;
                }
            }
            if nu12 * nu12 * e2 / e1 >= 1.0 {
                return Err(SectionError::Poisson {
                    what: what.to_string(),
                    value: nu12,
                });
            }
        }
    }
    Ok(())
}

/// A MAT2 in PSHELL role `role`: finite; as MID1 or MID2 (membrane, bending) positive
/// semi-definite, as MID3 G13 = G23 = G33 = 0 and [[G11, G12], [G12, G22]] positive
/// semi-definite; as MID4 (coupling, which may be indefinite) only finite. Semi-definite, not
/// definite: Nastran accepts e.g. G33 = 0, and a structure left without stiffness is caught
/// as singular where it is solved.
fn validate_anisotropic(what: &str, role: &str, g: &[[f64; 3]; 3]) -> Result<(), SectionError> {
    let bad = |why: &str| Err(SectionError::Roles(format!("{what} (MAT2): {why}")));
    if !g.iter().flatten().all(|x| x.is_finite()) {
        return bad("G11 … G33 must be finite");
    }
    let scale = g.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()));
    let tol = 1e-12 * scale;
    let minor2 = |i: usize, j: usize| g[i][i] * g[j][j] - g[i][j] * g[i][j];
    let det3 = g[0][0] * minor2(1, 2) - g[0][1] * (g[1][0] * g[2][2] - g[1][2] * g[2][0])
        + g[0][2] * (g[1][0] * g[2][1] - g[1][1] * g[2][0]);
    match role {
        "MID3" => {
            if g[0][2] != 0.0 || g[1][2] != 0.0 || g[2][2] != 0.0 {
                return bad(
                    "as MID3 (transverse shear from G11, G12, G22) G13, G23 and G33 must be blank",
                );
            }
            if g[0][0] < -tol || g[1][1] < -tol || minor2(0, 1) < -tol * scale {
                return bad(
                    "the transverse-shear matrix [[G11, G12], [G12, G22]] must not be negative in any direction",
                );
            }
        }
        "MID1" | "MID2" => {
            let diagonal = (0..3).all(|i| g[i][i] >= -tol);
            let minors = [(0, 1), (0, 2), (1, 2)]
                .iter()
                .all(|&(i, j)| minor2(i, j) >= -tol * scale);
            if !diagonal || !minors || det3 < -tol * scale * scale {
                return bad(
                    "G11 … G33 must form a positive semi-definite matrix (a material with negative stiffness in some direction)",
                );
            }
        }
        _ => {}
    }
    Ok(())
}

fn positive(what: &str, value: f64) -> Result<(), SectionError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(SectionError::NonPositive {
            what: what.into(),
            value,
        })
    }
}

/// In-plane Q and transverse-shear G of an isotropic material given by its plane-stress
/// λ* = Eν/(1−ν²) and μ = E/(2(1+ν)): Q = λ*·Q_λ + μ·Q_μ, G = μ·I₂ (linear in (λ*, μ)).
fn isotropic_matrices(lam: f64, mu: f64) -> (M3, M2) {
    (
        [
            [lam + 2.0 * mu, lam, 0.0],
            [lam, lam + 2.0 * mu, 0.0],
            [0.0, 0.0, mu],
        ],
        [[mu, 0.0], [0.0, mu]],
    )
}

/// In-plane Q and transverse-shear G of a role material (see [`ShellMaterial`]).
fn role_matrices(m: &ShellMaterial) -> (M3, M2) {
    match *m {
        ShellMaterial::Isotropic { e, nu } => {
            isotropic_matrices(e * nu / (1.0 - nu * nu), e / (2.0 * (1.0 + nu)))
        }
        ShellMaterial::Orthotropic {
            e1,
            e2,
            nu12,
            g12,
            g1z,
            g2z,
        } => {
            let (g1, g2) = transverse_moduli(g12, g1z, g2z);
            (orthotropic_q(e1, e2, nu12, g12), [[g1, 0.0], [0.0, g2]])
        }
        ShellMaterial::Anisotropic { g } => (g, [[g[0][0], g[0][1]], [g[1][0], g[1][1]]]),
    }
}

/// PSHELL stiffness ([`PshellSection`]) with the (Q, G) of each role given by `mats`; linear
/// in those matrices, which is what the affine split relies on.
fn pshell_stiffness(p: &PshellSection, mats: impl Fn(&RoleMaterial) -> (M3, M2)) -> ShellSection {
    let (t, z0) = (p.t, p.zoffs);
    let mut s = ShellSection::default();
    if let Some(m) = &p.membrane {
        let (q, _) = mats(m);
        s.a = m3_scale(&q, t);
        s.b = m3_scale(&q, t * z0);
        s.d = m3_scale(&q, t * z0 * z0);
        s.drill = DRILL_FRACTION * t * q[2][2];
    }
    if let Some(m) = &p.coupling {
        let (q, _) = mats(m);
        s.b = m3_add(&s.b, &m3_scale(&q, t * t));
        s.d = m3_add(&s.d, &m3_scale(&q, 2.0 * z0 * t * t));
    }
    if let Some(m) = &p.bending {
        let (q, _) = mats(m);
        s.d = m3_add(&s.d, &m3_scale(&q, p.bending_ratio * t.powi(3) / 12.0));
        if p.shear.is_none() {
            let k = KIRCHHOFF_SHEAR_PENALTY * p.bending_ratio * t * q[2][2];
            s.s = [[k, 0.0], [0.0, k]];
        }
    }
    if let Some(m) = &p.shear {
        let (_, g) = mats(m);
        s.s = m2_scale(&g, p.shear_ratio * t);
    }
    s
}

/// The material whose density gives the PSHELL mass: MID1, or MID2 when MID1 is blank.
fn mass_material(p: &PshellSection) -> Result<RoleMaterial, SectionError> {
    p.membrane
        .or(p.bending)
        .ok_or_else(|| SectionError::Roles("MID1 or MID2 must be given".into()))
}

/// PSHELL mass for density `rho` (with the NSM).
fn pshell_mass(p: &PshellSection, rho: f64) -> ShellMass {
    let (t, z0) = (p.t, p.zoffs);
    ShellMass {
        rho_t: rho * t + p.nsm,
        rho_s: rho * t * z0,
        rho_i: rho * (t.powi(3) / 12.0 + t * z0 * z0),
    }
}

/// Full ply stack (mirrored when symmetric), validated.
fn expand_plies(l: &Laminate) -> Result<Vec<Ply>, SectionError> {
    if l.plies.is_empty() {
        return Err(SectionError::NoPlies);
    }
    for (k, p) in l.plies.iter().enumerate() {
        let n = k + 1;
        positive(&format!("ply {n} thickness"), p.t)?;
        positive(&format!("ply {n} E1"), p.e1)?;
        positive(&format!("ply {n} E2"), p.e2)?;
        positive(&format!("ply {n} G12"), p.g12)?;
        if let Some(g) = p.g1z {
            positive(&format!("ply {n} G1Z"), g)?;
        }
        if let Some(g) = p.g2z {
            positive(&format!("ply {n} G2Z"), g)?;
        }
        if p.nu12 * p.nu12 * p.e2 / p.e1 >= 1.0 {
            return Err(SectionError::Poisson {
                what: format!("ply {n}"),
                value: p.nu12,
            });
        }
    }
    let mut plies = l.plies.clone();
    if l.symmetric {
        plies.extend(l.plies.iter().rev());
    }
    Ok(plies)
}

/// Interface coordinates z_0 < z_1 < … < z_n measured from the reference plane.
fn ply_interfaces(plies: &[Ply], z0: Option<f64>) -> Vec<f64> {
    let h: f64 = plies.iter().map(|p| p.t).sum();
    let mut z = vec![z0.unwrap_or(-0.5 * h)];
    for p in plies {
        z.push(z[z.len() - 1] + p.t);
    }
    z
}

fn ply_mass(rho: f64, z1: f64, z2: f64) -> ShellMass {
    ShellMass {
        rho_t: rho * (z2 - z1),
        rho_s: rho * 0.5 * (z2 * z2 - z1 * z1),
        rho_i: rho * (z2.powi(3) - z1.powi(3)) / 3.0,
    }
}

/// Plane-stress reduced stiffness of a ply in its own axes (1 = fibre):
/// Q11 = E1/Δ, Q22 = E2/Δ, Q12 = ν12·E2/Δ, Q66 = G12, Δ = 1 − ν12ν21, ν21 = ν12E2/E1.
fn ply_q(p: &Ply) -> M3 {
    orthotropic_q(p.e1, p.e2, p.nu12, p.g12)
}

/// The Q of [`ply_q`] from the constants.
fn orthotropic_q(e1: f64, e2: f64, nu12: f64, g12: f64) -> M3 {
    let del = 1.0 - nu12 * nu12 * e2 / e1;
    let (q11, q22, q12) = (e1 / del, e2 / del, nu12 * e2 / del);
    [[q11, q12, 0.0], [q12, q22, 0.0], [0.0, 0.0, g12]]
}

/// Transverse shear moduli (G1Z, G2Z) of a ply, penalty for the absent ones.
fn ply_g(p: &Ply) -> (f64, f64) {
    transverse_moduli(p.g12, p.g1z, p.g2z)
}

/// (G1Z, G2Z), a blank one replaced by the penalty `KIRCHHOFF_SHEAR_PENALTY · G12`.
fn transverse_moduli(g12: f64, g1z: Option<f64>, g2z: Option<f64>) -> (f64, f64) {
    let pen = KIRCHHOFF_SHEAR_PENALTY * g12;
    (g1z.unwrap_or(pen), g2z.unwrap_or(pen))
}

/// Q̄ = T_εᵀ Q T_ε, T_ε = [[c², s², cs], [s², c², −cs], [−2cs, 2cs, c²−s²]] (engineering strains
/// of the laminate axes → ply axes).
fn qbar_rotated(q: &M3, theta_deg: f64) -> M3 {
    let (s, c) = theta_deg.to_radians().sin_cos();
    let t = [
        [c * c, s * s, c * s],
        [s * s, c * c, -c * s],
        [-2.0 * c * s, 2.0 * c * s, c * c - s * s],
    ];
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let mut v = 0.0;
            for k in 0..3 {
                for l in 0..3 {
                    v += t[k][i] * q[k][l] * t[l][j];
                }
            }
            v
        })
    })
}

/// Q̄s = Rᵀ diag(G1Z, G2Z) R with R = [[c, s], [−s, c]] (order xz, yz).
fn qbar_shear_rotated(p: &Ply, theta_deg: f64) -> M2 {
    let (s, c) = theta_deg.to_radians().sin_cos();
    let (g1, g2) = ply_g(p);
    [
        [g1 * c * c + g2 * s * s, (g1 - g2) * c * s],
        [(g1 - g2) * c * s, g1 * s * s + g2 * c * c],
    ]
}

/// The five Θ functions of eq. 3.18 in the order of [`THETA_COEFFICIENTS`].
const THETA_COEFFICIENTS: [Coefficient; 5] = [
    Coefficient::Cos4,
    Coefficient::Sin4,
    Coefficient::Cos2Sin2,
    Coefficient::CosSin3,
    Coefficient::Cos3Sin,
];

/// Q̄(Θ) = Σ_i f_i(Θ) X_i over the functions of eq. 3.18 (order of `THETA_COEFFICIENTS`):
/// Q̄11 = Q11c⁴ + Q22s⁴ + 2(Q12+2Q66)c²s², Q̄22 likewise with Q11↔Q22,
/// Q̄12 = Q12(c⁴+s⁴) + (Q11+Q22−4Q66)c²s², Q̄66 = Q66(c⁴+s⁴) + (Q11+Q22−2Q12−2Q66)c²s²,
/// Q̄16 = (Q11−Q12−2Q66)c³s + (Q12−Q22+2Q66)cs³, Q̄26 likewise with c³s↔cs³.
/// The odd functions (cs³, c³s) are multiplied by `sign` (−1 for a ply at −Θ).
fn qbar_parts(q: &M3, sign: f64) -> [M3; 5] {
    let (q11, q22, q12, q66) = (q[0][0], q[1][1], q[0][1], q[2][2]);
    let sym = |a11: f64, a22: f64, a12: f64, a66: f64, a16: f64, a26: f64| -> M3 {
        [[a11, a12, a16], [a12, a22, a26], [a16, a26, a66]]
    };
    let (p, r) = (q11 - q12 - 2.0 * q66, q12 - q22 + 2.0 * q66);
    [
        sym(q11, q22, q12, q66, 0.0, 0.0),
        sym(q22, q11, q12, q66, 0.0, 0.0),
        sym(
            2.0 * (q12 + 2.0 * q66),
            2.0 * (q12 + 2.0 * q66),
            q11 + q22 - 4.0 * q66,
            q11 + q22 - 2.0 * q12 - 2.0 * q66,
            0.0,
            0.0,
        ),
        sym(0.0, 0.0, 0.0, 0.0, sign * r, sign * p),
        sym(0.0, 0.0, 0.0, 0.0, sign * p, sign * r),
    ]
}

/// Q̄s(Θ) = Σ f_i X_i: c² = c⁴ + c²s², s² = s⁴ + c²s², cs = c³s + cs³, so
/// Q̄s_xx = G1Z c² + G2Z s², Q̄s_yy = G1Z s² + G2Z c², Q̄s_xy = (G1Z − G2Z) cs.
fn qbar_shear_parts(p: &Ply, sign: f64) -> [M2; 5] {
    let (g1, g2) = ply_g(p);
    let odd = sign * (g1 - g2);
    [
        [[g1, 0.0], [0.0, g2]],
        [[g2, 0.0], [0.0, g1]],
        [[g1 + g2, 0.0], [0.0, g1 + g2]],
        [[0.0, odd], [odd, 0.0]],
        [[0.0, odd], [odd, 0.0]],
    ]
}

/// Σ_i f_i(v) section_i.
pub fn evaluate(parts: &[(Coefficient, ShellSection)], v: &CoefficientValues) -> ShellSection {
    parts.iter().fold(ShellSection::default(), |acc, (c, s)| {
        acc.plus(&s.scaled(c.value(v)))
    })
}

/// Split a section into affine parts, Σ f_i(p) section_i = section(p) exactly (stiffness and
/// mass; parts with zero stiffness carry mass only and vice versa):
///
/// | parameter | PSHELL (material m = `parametrized`) | laminate |
/// |---|---|---|
/// | `E` | (E: roles using m, with E = 1), (Constant: other roles, mass) | refused |
/// | `Nu` | (λ*: roles using m with Q_λ), (μ: with Q_μ and G = I₂), (Constant: other roles, mass) | refused |
/// | `Rho` | (Rho: mass/ρ without NSM), (Constant: stiffness, NSM) when m is the mass material; else all constant | same, one ply density |
/// | `Theta` | refused | five functions of eq. 3.18, (Constant: mass) |
/// | `Tply` | refused | (H: A, S, drill, ρt), (H²: B, ρs), (H³: D, ρi), (Constant: NSM) |
///
/// With Q_λ = [[1,1,0],[1,1,0],[0,0,0]] and Q_μ = [[2,0,0],[0,2,0],[0,0,1]] (eq. 3.13 in plane
/// stress). A PSHELL is linear in the Q, G of each role (A, B, D, S, drill and the Kirchhoff
/// penalty alike, [`PshellSection`]), so E on the MID2 material scales D only, E on the MID1
/// material A, the drill and the offset terms z₀A, z₀²A, and so on. E and NU need m to be a
/// MAT1 (isotropic) material. `Theta` uses the Θ functions for A, B, D, S and the drill (∝ A66)
/// without a constant term (c⁴ + 2c²s² + s⁴ = 1 makes one unnecessary).
pub fn affine_sections(
    data: &SectionData,
    parameter: SectionParameter,
) -> Result<Vec<(Coefficient, ShellSection)>, SectionError> {
    match data {
        SectionData::Pshell {
            section,
            parametrized,
        } => affine_pshell(section, *parametrized, parameter),
        SectionData::Laminate(l) => affine_laminate(l, parameter),
    }
}

fn affine_pshell(
    p: &PshellSection,
    target: u32,
    parameter: SectionParameter,
) -> Result<Vec<(Coefficient, ShellSection)>, SectionError> {
    let full = ShellSection::pshell(p)?;
    let zero = ([[0.0; 3]; 3], [[0.0; 2]; 2]);
    let others = pshell_stiffness(p, |m| {
        if m.mid == target {
            zero
        } else {
            role_matrices(&m.material)
        }
    });
    let mass = ShellSection::mass_only(full.mass);
    // The target's ν (isotropic; all roles of one id share the material).
    let target_nu = || {
        let roles = [p.membrane, p.bending, p.shear, p.coupling];
        let mut nu = None;
        for m in roles.iter().flatten().filter(|m| m.mid == target) {
            match m.material {
                ShellMaterial::Isotropic { nu: n, .. } => nu = Some(n),
                ShellMaterial::Orthotropic { .. } => {
                    return Err(SectionError::UnsupportedParameter {
                        parameter,
                        section: "MAT8 PSHELL",
                    });
                }
                ShellMaterial::Anisotropic { .. } => {
                    return Err(SectionError::UnsupportedParameter {
                        parameter,
                        section: "MAT2 PSHELL",
                    });
                }
            }
        }
        Ok(nu.unwrap_or(0.0))
    };
    let unit = |lam: f64, mu: f64| {
        pshell_stiffness(p, |m| {
            if m.mid == target {
                isotropic_matrices(lam, mu)
            } else {
                zero
            }
        })
    };
    Ok(match parameter {
        SectionParameter::E => {
            let nu = target_nu()?;
            vec![
                (
                    Coefficient::E,
                    unit(nu / (1.0 - nu * nu), 1.0 / (2.0 * (1.0 + nu))),
                ),
                (Coefficient::Constant, others.plus(&mass)),
            ]
        }
        SectionParameter::Nu => {
            target_nu()?;
            vec![
                (Coefficient::LambdaPlaneStress, unit(1.0, 0.0)),
                (Coefficient::Mu, unit(0.0, 1.0)),
                (Coefficient::Constant, others.plus(&mass)),
            ]
        }
        SectionParameter::Rho if mass_material(p)?.mid == target => {
            let unit_mass = pshell_mass(&PshellSection { nsm: 0.0, ..*p }, 1.0);
            vec![
                (Coefficient::Rho, ShellSection::mass_only(unit_mass)),
                (
                    Coefficient::Constant,
                    ShellSection {
                        mass: ShellMass {
                            rho_t: p.nsm,
                            ..ShellMass::default()
                        },
                        ..full
                    },
                ),
            ]
        }
        SectionParameter::Rho => vec![(Coefficient::Constant, full)],
        SectionParameter::Theta | SectionParameter::Tply => {
            return Err(SectionError::UnsupportedParameter {
                parameter,
                section: "PSHELL",
            });
        }
    })
}

fn affine_laminate(
    l: &Laminate,
    parameter: SectionParameter,
) -> Result<Vec<(Coefficient, ShellSection)>, SectionError> {
    let plies = expand_plies(l)?;
    let full = ShellSection::laminate(l)?;
    let nsm_only = ShellSection::mass_only(ShellMass {
        rho_t: l.nsm,
        ..ShellMass::default()
    });
    let z = ply_interfaces(&plies, l.z0);
    match parameter {
        SectionParameter::Theta => {
            let mut parts: Vec<(Coefficient, ShellSection)> = THETA_COEFFICIENTS
                .iter()
                .map(|&c| (c, ShellSection::default()))
                .collect();
            for (k, p) in plies.iter().enumerate() {
                let sign = if p.theta_deg >= 0.0 { 1.0 } else { -1.0 };
                let (z1, z2) = (z[k], z[k + 1]);
                let qs = qbar_parts(&ply_q(p), sign);
                let gs = qbar_shear_parts(p, sign);
                for (i, (_, s)) in parts.iter_mut().enumerate() {
                    s.a = m3_add(&s.a, &m3_scale(&qs[i], z2 - z1));
                    s.b = m3_add(&s.b, &m3_scale(&qs[i], 0.5 * (z2 * z2 - z1 * z1)));
                    s.d = m3_add(&s.d, &m3_scale(&qs[i], (z2.powi(3) - z1.powi(3)) / 3.0));
                    s.s = m2_add(&s.s, &m2_scale(&gs[i], SHEAR_CORRECTION * (z2 - z1)));
                }
            }
            for (_, s) in &mut parts {
                s.drill = DRILL_FRACTION * s.a[2][2];
            }
            parts.push((Coefficient::Constant, ShellSection::mass_only(full.mass)));
            Ok(parts)
        }
        SectionParameter::Tply => {
            uniform(&plies, parameter, "thickness", |p| p.t)?;
            // Scale-free laminate: every length divided by the ply thickness h.
            let h = plies[0].t;
            let unit = Laminate {
                plies: l.plies.iter().map(|p| Ply { t: 1.0, ..*p }).collect(),
                z0: l.z0.map(|z0| z0 / h),
                nsm: 0.0,
                symmetric: l.symmetric,
            };
            let u = ShellSection::laminate(&unit)?;
            let zero3 = [[0.0; 3]; 3];
            let part = |a: M3, b: M3, d: M3, s: M2, drill: f64, mass: ShellMass| ShellSection {
                a,
                b,
                d,
                s,
                drill,
                mass,
            };
            Ok(vec![
                (
                    Coefficient::H,
                    part(
                        u.a,
                        zero3,
                        zero3,
                        u.s,
                        u.drill,
                        ShellMass {
                            rho_t: u.mass.rho_t,
                            ..ShellMass::default()
                        },
                    ),
                ),
                (
                    Coefficient::H2,
                    part(
                        zero3,
                        u.b,
                        zero3,
                        [[0.0; 2]; 2],
                        0.0,
                        ShellMass {
                            rho_s: u.mass.rho_s,
                            ..ShellMass::default()
                        },
                    ),
                ),
                (
                    Coefficient::H3,
                    part(
                        zero3,
                        zero3,
                        u.d,
                        [[0.0; 2]; 2],
                        0.0,
                        ShellMass {
                            rho_i: u.mass.rho_i,
                            ..ShellMass::default()
                        },
                    ),
                ),
                (Coefficient::Constant, nsm_only),
            ])
        }
        SectionParameter::Rho => {
            uniform(&plies, parameter, "density", |p| p.rho)?;
            let mut unit_mass = ShellMass::default();
            for k in 0..plies.len() {
                unit_mass = unit_mass.plus(&ply_mass(1.0, z[k], z[k + 1]));
            }
            Ok(vec![
                (Coefficient::Rho, ShellSection::mass_only(unit_mass)),
                (Coefficient::Constant, full.without_mass().plus(&nsm_only)),
            ])
        }
        SectionParameter::E | SectionParameter::Nu => Err(SectionError::UnsupportedParameter {
            parameter,
            section: "laminate",
        }),
    }
}

/// Check that `value` is the same for every ply.
fn uniform(
    plies: &[Ply],
    parameter: SectionParameter,
    what: &'static str,
    value: impl Fn(&Ply) -> f64,
) -> Result<(), SectionError> {
    let first = value(&plies[0]);
    match plies.iter().position(|p| value(p) != first) {
        None => Ok(()),
        Some(k) => Err(SectionError::NotUniform {
            parameter,
            what,
            first,
            ply: k + 1,
            value: value(&plies[k]),
        }),
    }
}

/// Strains and stresses of one ply at its mid-plane, in the ply axes (1 = fibre, 2 = across,
/// z = element normal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlyState {
    /// The ply's mid-plane z from the reference plane.
    pub z: f64,
    /// [ε1, ε2, γ12, γ1z, γ2z] (engineering shear strains).
    pub strain: [f64; 5],
    /// [σ1, σ2, τ12, τ1z, τ2z].
    pub stress: [f64; 5],
}

/// The [`PlyState`] of every ply of `l` (the full stack, bottom first) for the reference-plane
/// strains ε⁰ (`membrane`), curvatures κ and transverse shear strains γ = [γxz, γyz], all in the
/// element material axes (CLT, thesis eq. 2.7–2.8): ε(z) = ε⁰ + zκ at the ply's mid-plane,
/// rotated into the ply axes by the engineering-strain rotation T_ε(Θ), σ = Q ε with the ply's
/// reduced stiffness; the transverse shear strain is constant through the thickness (first-order
/// shear theory, the strain the section's S = 5/6 Σ Q̄s t is consistent with), rotated by
/// [[c, s], [−s, c]], τ = diag(G1Z, G2Z) γ (a blank modulus is the penalty of
/// [`KIRCHHOFF_SHEAR_PENALTY`], so τ is then the penalty's, ≈ 6/5 of the mean shear Q/h).
///
/// `thermal` holds each ply's free thermal strain {ε1 ε2 γ12} in its own axes (full stack
/// order; empty without a thermal load): the stress is then Q (ε − ε_th), the strain reported
/// the total ε, as Nastran reports element strains.
pub fn ply_states(
    l: &Laminate,
    membrane: [f64; 3],
    curvature: [f64; 3],
    shear: [f64; 2],
    thermal: &[[f64; 3]],
) -> Result<Vec<PlyState>, SectionError> {
    let plies = expand_plies(l)?;
    let z = ply_interfaces(&plies, l.z0);
    Ok(plies
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let zm = 0.5 * (z[k] + z[k + 1]);
            let angle = p.theta_deg.to_radians();
            let t = super::shell::strain_rotation(angle);
            let e: [f64; 3] = std::array::from_fn(|i| membrane[i] + zm * curvature[i]);
            let ep: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| t[i][j] * e[j]).sum());
            let q = ply_q(p);
            let th = thermal.get(k).copied().unwrap_or_default();
            let sp: [f64; 3] =
                std::array::from_fn(|i| (0..3).map(|j| q[i][j] * (ep[j] - th[j])).sum());
            let (sn, c) = angle.sin_cos();
            let g = [c * shear[0] + sn * shear[1], -sn * shear[0] + c * shear[1]];
            let (g1, g2) = ply_g(p);
            PlyState {
                z: zm,
                strain: [ep[0], ep[1], ep[2], g[0], g[1]],
                stress: [sp[0], sp[1], sp[2], g1 * g[0], g2 * g[1]],
            }
        })
        .collect())
}

/// The thermal resultants (N_T, M_T) about the reference plane of a laminate whose plies have
/// the free thermal strains `thermal` ({ε1 ε2 γ12} in each ply's axes, full stack order):
///
/// ```text
/// N_T = Σ_k Q̄_k ᾱ_k (z_{k+1} − z_k),   M_T = Σ_k Q̄_k ᾱ_k (z_{k+1}² − z_k²)/2
/// ```
///
/// with Q̄_k ᾱ_k = T_εᵀ Q_k α_k (ᾱ = T_ε⁻¹ α, Q̄ = T_εᵀ Q T_ε): the resultants of the stresses
/// −Q̄_k ᾱ_k a fully restrained laminate carries, with the sign reversed (Jones, *Mechanics of
/// Composite Materials*, 2nd ed. 1999, §4.8).
pub fn thermal_resultants(
    l: &Laminate,
    thermal: &[[f64; 3]],
) -> Result<([f64; 3], [f64; 3]), SectionError> {
    let plies = expand_plies(l)?;
    let z = ply_interfaces(&plies, l.z0);
    let (mut n, mut m) = ([0.0; 3], [0.0; 3]);
    for (k, p) in plies.iter().enumerate() {
        let th = thermal.get(k).copied().unwrap_or_default();
        let q = ply_q(p);
        let sigma: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| q[i][j] * th[j]).sum());
        let t = super::shell::strain_rotation(p.theta_deg.to_radians());
        // T_εᵀ σ: the ply-axes stress of the thermal strain as laminate-axes resultant density
        let s: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| t[j][i] * sigma[j]).sum());
        let (z1, z2) = (z[k], z[k + 1]);
        for i in 0..3 {
            n[i] += s[i] * (z2 - z1);
            m[i] += s[i] * 0.5 * (z2 * z2 - z1 * z1);
        }
    }
    Ok((n, m))
}

#[cfg(test)]
impl PshellSection {
    /// MID1 = MID2 = MID3 = `m`, 12I/T³ = 1, TS/T = 5/6, no NSM, no offset (tests).
    pub(crate) fn homogeneous(m: RoleMaterial, t: f64) -> Self {
        Self {
            t,
            membrane: Some(m),
            bending: Some(m),
            bending_ratio: 1.0,
            shear: Some(m),
            shear_ratio: 5.0 / 6.0,
            coupling: None,
            nsm: 0.0,
            zoffs: 0.0,
        }
    }
}

#[cfg(test)]
impl RoleMaterial {
    /// A MAT1 role material (tests).
    pub(crate) fn mat1(mid: u32, e: f64, nu: f64, rho: f64) -> Self {
        Self {
            mid,
            material: ShellMaterial::Isotropic { e, nu },
            rho,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ply(theta_deg: f64) -> Ply {
        // T300/5208-like ply: E1 = 181 GPa, E2 = 10.3 GPa, ν12 = 0.28, G12 = 7.17 GPa.
        Ply {
            e1: 181.0e9,
            e2: 10.3e9,
            nu12: 0.28,
            g12: 7.17e9,
            g1z: Some(7.17e9),
            g2z: Some(3.0e9),
            rho: 1600.0,
            t: 0.125e-3,
            theta_deg,
        }
    }

    fn close3(a: &M3, b: &M3, tol: f64) -> bool {
        let scale = a
            .iter()
            .chain(b.iter())
            .flatten()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| (x - y).abs() <= tol * scale.max(f64::MIN_POSITIVE))
    }

    fn sections_close(a: &ShellSection, b: &ShellSection, tol: f64) -> bool {
        let near = |x: f64, y: f64, s: f64| (x - y).abs() <= tol * s.max(f64::MIN_POSITIVE);
        let sd = b.s.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        close3(&a.a, &b.a, tol)
            && close3(&a.d, &b.d, tol)
            && (close3(&a.b, &b.b, tol) || {
                // B of a symmetric laminate is round-off: compare to the A·h scale.
                let s = b.a[0][0] * 1e-3;
                a.b.iter()
                    .flatten()
                    .zip(b.b.iter().flatten())
                    .all(|(x, y)| near(*x, *y, s))
            })
            && a.s
                .iter()
                .flatten()
                .zip(b.s.iter().flatten())
                .all(|(x, y)| near(*x, *y, sd))
            && near(a.drill, b.drill, b.drill.abs())
            && near(a.mass.rho_t, b.mass.rho_t, b.mass.rho_t.abs())
            && near(a.mass.rho_s, b.mass.rho_s, b.mass.rho_t.abs() * 1e-3)
            && near(a.mass.rho_i, b.mass.rho_i, b.mass.rho_i.abs())
    }

    /// [0/90]s, each ply t = 0.125 mm, h = 0.5 mm. With Δ = 1 − ν12²E2/E1:
    /// Q11 = E1/Δ, Q22 = E2/Δ, Q12 = ν12E2/Δ, Q66 = G12 (90° ply: Q11 ↔ Q22).
    /// A11 = A22 = (Q11 + Q22)·2t, A12 = Q12·4t, A66 = G12·4t, A16 = A26 = 0, B = 0.
    /// D11 = Q11·(0.25³ − 0.125³)·2/3 mm³ + Q22·0.125³·2/3 mm³, D22 with Q11 ↔ Q22,
    /// D12 = Q12·h³/12, D66 = G12·h³/12.
    #[test]
    fn cross_ply_0_90_s_by_hand() {
        let lam = Laminate {
            plies: vec![ply(0.0), ply(90.0)],
            z0: None,
            nsm: 0.0,
            symmetric: true,
        };
        let s = ShellSection::laminate(&lam).unwrap();
        let p = ply(0.0);
        let del = 1.0 - p.nu12 * p.nu12 * p.e2 / p.e1;
        let (q11, q22, q12, q66) = (p.e1 / del, p.e2 / del, p.nu12 * p.e2 / del, p.g12);
        let t = 0.125e-3;
        let h = 4.0 * t;
        let a = [
            [(q11 + q22) * 2.0 * t, q12 * 4.0 * t, 0.0],
            [q12 * 4.0 * t, (q11 + q22) * 2.0 * t, 0.0],
            [0.0, 0.0, q66 * 4.0 * t],
        ];
        let outer = (0.25e-3f64.powi(3) - 0.125e-3f64.powi(3)) * 2.0 / 3.0;
        let inner = 0.125e-3f64.powi(3) * 2.0 / 3.0;
        let d = [
            [q11 * outer + q22 * inner, q12 * h.powi(3) / 12.0, 0.0],
            [q12 * h.powi(3) / 12.0, q22 * outer + q11 * inner, 0.0],
            [0.0, 0.0, q66 * h.powi(3) / 12.0],
        ];
        assert!(close3(&s.a, &a, 1e-13), "{:?}\n{:?}", s.a, a);
        assert!(close3(&s.d, &d, 1e-13), "{:?}\n{:?}", s.d, d);
        assert!(s.b.iter().flatten().all(|x| x.abs() < 1e-12 * q11 * t * t));
        // S = 5/6·(G1Z·2t + G2Z·2t) in both directions (0° and 90° plies swap G1Z, G2Z).
        let sxx = 5.0 / 6.0 * (7.17e9 + 3.0e9) * 2.0 * t;
        assert!((s.s[0][0] - sxx).abs() < 1e-12 * sxx && (s.s[1][1] - sxx).abs() < 1e-12 * sxx);
        assert!((s.drill - DRILL_FRACTION * q66 * h).abs() < 1e-12 * s.drill);
        assert!((s.mass.rho_t - 1600.0 * h).abs() < 1e-12);
    }

    /// Antisymmetric [+45/−45], t each, h = 2t. At ±45°: c⁴ = s⁴ = c²s² = cs³ = c³s = 1/4, so
    /// Q̄11 = Q̄22 = (Q11 + Q22 + 2Q12 + 4Q66)/4, Q̄12 = (Q11 + Q22 + 2Q12 − 4Q66)/4,
    /// Q̄66 = (Q11 + Q22 − 2Q12)/4, Q̄16 = Q̄26 = ±(Q11 − Q22)/4.
    /// A = Q̄·h with A16 = A26 = 0; B16 = B26 = ½[Q̄16⁻(0 − t²) + Q̄16⁺(t² − 0)] = −(Q11−Q22)t²/4
    /// (bottom ply +45: Q̄16⁺(0 − t²)/2 + Q̄16⁻(t² − 0)/2 with Q̄16⁻ = −Q̄16⁺), other B = 0;
    /// D = Q̄·h³/12 with D16 = D26 = 0.
    #[test]
    fn antisymmetric_angle_ply_by_hand() {
        let lam = Laminate {
            plies: vec![ply(45.0), ply(-45.0)],
            z0: None,
            nsm: 0.0,
            symmetric: false,
        };
        let s = ShellSection::laminate(&lam).unwrap();
        let p = ply(0.0);
        let del = 1.0 - p.nu12 * p.nu12 * p.e2 / p.e1;
        let (q11, q22, q12, q66) = (p.e1 / del, p.e2 / del, p.nu12 * p.e2 / del, p.g12);
        let t = 0.125e-3;
        let h = 2.0 * t;
        let qb11 = (q11 + q22 + 2.0 * q12 + 4.0 * q66) / 4.0;
        let qb12 = (q11 + q22 + 2.0 * q12 - 4.0 * q66) / 4.0;
        let qb66 = (q11 + q22 - 2.0 * q12) / 4.0;
        let qb16 = (q11 - q22) / 4.0;
        let a = [
            [qb11 * h, qb12 * h, 0.0],
            [qb12 * h, qb11 * h, 0.0],
            [0.0, 0.0, qb66 * h],
        ];
        let b16 = -qb16 * t * t;
        let b = [[0.0, 0.0, b16], [0.0, 0.0, b16], [b16, b16, 0.0]];
        let h3 = h.powi(3) / 12.0;
        let d = [
            [qb11 * h3, qb12 * h3, 0.0],
            [qb12 * h3, qb11 * h3, 0.0],
            [0.0, 0.0, qb66 * h3],
        ];
        assert!(close3(&s.a, &a, 1e-13), "{:?}\n{:?}", s.a, a);
        assert!(close3(&s.b, &b, 1e-13), "{:?}\n{:?}", s.b, b);
        assert!(close3(&s.d, &d, 1e-13), "{:?}\n{:?}", s.d, d);
    }

    /// Isotropic PSHELL by hand, with offset: B = A·z₀, D = Eh³/(12(1−ν²))·r + A z₀².
    #[test]
    fn isotropic_offset_by_hand() {
        let p = PshellSection {
            nsm: 0.5,
            zoffs: 1e-3,
            ..PshellSection::homogeneous(RoleMaterial::mat1(1, 70e9, 0.3, 2700.0), 2e-3)
        };
        let s = ShellSection::pshell(&p).unwrap();
        let a11 = 70e9 * 2e-3 / (1.0 - 0.09);
        assert!((s.a[0][0] - a11).abs() < 1e-12 * a11);
        assert!((s.b[0][1] - 0.3 * a11 * 1e-3).abs() < 1e-12 * a11 * 1e-3);
        let d11 = a11 * (4e-6 / 12.0 + 1e-6);
        assert!((s.d[0][0] - d11).abs() < 1e-12 * d11);
        let g = 70e9 / 2.6;
        assert!((s.s[0][0] - 5.0 / 6.0 * g * 2e-3).abs() < 1e-3);
        assert!((s.mass.rho_t - (2700.0 * 2e-3 + 0.5)).abs() < 1e-12);
        // A PSHELL whose roles are one MAT8 with isotropic constants, and a one-ply PCOMP of
        // it (CLT, shear factor 5/6 = TS/T here), both equal the MAT1 PSHELL.
        let ply = Ply {
            e1: 70e9,
            e2: 70e9,
            nu12: 0.3,
            g12: g,
            g1z: Some(g),
            g2z: Some(g),
            rho: 2700.0,
            t: 2e-3,
            theta_deg: 0.0,
        };
        let mat8 = RoleMaterial {
            mid: 8,
            material: ShellMaterial::Orthotropic {
                e1: ply.e1,
                e2: ply.e2,
                nu12: ply.nu12,
                g12: g,
                g1z: ply.g1z,
                g2z: ply.g2z,
            },
            rho: 2700.0,
        };
        let o = ShellSection::pshell(&PshellSection {
            nsm: 0.5,
            zoffs: 1e-3,
            ..PshellSection::homogeneous(mat8, 2e-3)
        })
        .unwrap();
        assert!(sections_close(&o, &s, 1e-12), "{o:?}\n{s:?}");
        let lam = Laminate {
            plies: vec![ply],
            z0: Some(1e-3 - 1e-3),
            nsm: 0.5,
            symmetric: false,
        };
        let l = ShellSection::laminate(&lam).unwrap();
        assert!(sections_close(&l, &s, 1e-12), "{l:?}\n{s:?}");
    }

    fn mat8(mid: u32) -> RoleMaterial {
        let p = ply(0.0);
        RoleMaterial {
            mid,
            material: ShellMaterial::Orthotropic {
                e1: p.e1,
                e2: p.e2,
                nu12: p.nu12,
                g12: p.g12,
                g1z: p.g1z,
                g2z: None,
            },
            rho: p.rho,
        }
    }

    /// A PSHELL with four different materials (Nastran QRG PSHELL): MID1 MAT1 (E1, ν1),
    /// MID2 MAT1 (E2, ν2), MID3 MAT8 (G1Z given, G2Z blank = penalty 100·G12), MID4 MAT1,
    /// offset z₀, r = 12I/T³, ts = TS/T:
    /// A = T Q1, B = T² Q4 + z₀ T Q1, D = r T³/12 Q2 + 2 z₀ T² Q4 + z₀² T Q1,
    /// S = ts T diag(G1Z, 100 G12), drill = DRILL_FRACTION·A66, mass ρ1 T + NSM, ρ1 T z₀, ρ1(T³/12 + T z₀²).
    #[test]
    fn distinct_role_materials_by_hand() {
        let (t, z0, r, ts, nsm) = (4e-3, 1.5e-3, 0.37, 0.7, 0.25);
        let m1 = RoleMaterial::mat1(1, 70e9, 0.33, 2700.0);
        let m2 = RoleMaterial::mat1(2, 210e9, 0.28, 7850.0);
        let m4 = RoleMaterial::mat1(4, 3e9, 0.1, 1.0);
        let p = PshellSection {
            t,
            membrane: Some(m1),
            bending: Some(m2),
            bending_ratio: r,
            shear: Some(mat8(3)),
            shear_ratio: ts,
            coupling: Some(m4),
            nsm,
            zoffs: z0,
        };
        let s = ShellSection::pshell(&p).unwrap();
        let q = |e: f64, nu: f64| {
            let c = e / (1.0 - nu * nu);
            [
                [c, c * nu, 0.0],
                [c * nu, c, 0.0],
                [0.0, 0.0, e / (2.0 * (1.0 + nu))],
            ]
        };
        let (q1, q2, q4) = (q(70e9, 0.33), q(210e9, 0.28), q(3e9, 0.1));
        let lin = |terms: &[(&M3, f64)]| -> M3 {
            std::array::from_fn(|i| {
                std::array::from_fn(|j| terms.iter().map(|(m, f)| m[i][j] * f).sum())
            })
        };
        let a = lin(&[(&q1, t)]);
        let b = lin(&[(&q4, t * t), (&q1, z0 * t)]);
        let d = lin(&[
            (&q2, r * t.powi(3) / 12.0),
            (&q4, 2.0 * z0 * t * t),
            (&q1, z0 * z0 * t),
        ]);
        assert!(close3(&s.a, &a, 1e-14), "{:?}\n{a:?}", s.a);
        assert!(close3(&s.b, &b, 1e-14), "{:?}\n{b:?}", s.b);
        assert!(close3(&s.d, &d, 1e-14), "{:?}\n{d:?}", s.d);
        let p8 = ply(0.0);
        let sxx = ts * t * p8.g1z.unwrap();
        let syy = ts * t * KIRCHHOFF_SHEAR_PENALTY * p8.g12;
        assert!((s.s[0][0] - sxx).abs() <= 1e-15 * sxx && (s.s[1][1] - syy).abs() <= 1e-15 * syy);
        assert_eq!((s.s[0][1], s.s[1][0]), (0.0, 0.0));
        assert!((s.drill - DRILL_FRACTION * a[2][2]).abs() <= 1e-15 * s.drill);
        let want = ShellMass {
            rho_t: 2700.0 * t + nsm,
            rho_s: 2700.0 * t * z0,
            rho_i: 2700.0 * (t.powi(3) / 12.0 + t * z0 * z0),
        };
        assert!((s.mass.rho_t - want.rho_t).abs() <= 1e-15 * want.rho_t);
        assert!((s.mass.rho_s - want.rho_s).abs() <= 1e-15 * want.rho_s);
        assert!((s.mass.rho_i - want.rho_i).abs() <= 1e-15 * want.rho_i);
        // MID1 blank: no membrane, no drill, mass from MID2 (Nastran).
        let bending_only = PshellSection {
            membrane: None,
            coupling: None,
            zoffs: 0.0,
            ..p
        };
        let s = ShellSection::pshell(&bending_only).unwrap();
        assert_eq!((s.a, s.b, s.drill), ([[0.0; 3]; 3], [[0.0; 3]; 3], 0.0));
        assert!((s.mass.rho_t - (7850.0 * t + nsm)).abs() <= 1e-15 * s.mass.rho_t);
        // MID2 blank: membrane only.
        let membrane_only = PshellSection {
            bending: None,
            shear: None,
            coupling: None,
            zoffs: 0.0,
            ..p
        };
        let s = ShellSection::pshell(&membrane_only).unwrap();
        assert!(close3(&s.a, &a, 1e-14));
        assert_eq!(
            (s.b, s.d, s.s),
            ([[0.0; 3]; 3], [[0.0; 3]; 3], [[0.0; 2]; 2])
        );
        // MID3 blank: S = 100 · r · G2 · T.
        let kirchhoff = PshellSection { shear: None, ..p };
        let s = ShellSection::pshell(&kirchhoff).unwrap();
        let pen = KIRCHHOFF_SHEAR_PENALTY * r * q2[2][2] * t;
        assert!((s.s[0][0] - pen).abs() <= 1e-15 * pen && s.s[0][1] == 0.0);
        assert_eq!(s.s[0][0], s.s[1][1]);
    }

    /// 12I/T³ = k with MID2 E is the same section as 12I/T³ = 1 with MID2 E·k (D ∝ r·E), and
    /// as 12I/T³ = 1 with a MID2 of k·E in the Kirchhoff penalty too.
    #[test]
    fn bending_ratio_equals_scaled_bending_modulus() {
        let k = 0.43;
        let m1 = RoleMaterial::mat1(1, 70e9, 0.33, 2700.0);
        let base = PshellSection {
            bending_ratio: k,
            bending: Some(RoleMaterial::mat1(2, 200e9, 0.3, 0.0)),
            shear: None,
            ..PshellSection::homogeneous(m1, 3e-3)
        };
        let scaled = PshellSection {
            bending_ratio: 1.0,
            bending: Some(RoleMaterial::mat1(2, 200e9 * k, 0.3, 0.0)),
            ..base
        };
        let (a, b) = (
            ShellSection::pshell(&base).unwrap(),
            ShellSection::pshell(&scaled).unwrap(),
        );
        assert!(sections_close(&a, &b, 1e-15), "{a:?}\n{b:?}");
    }

    #[test]
    fn bad_input_is_an_error() {
        let m = RoleMaterial::mat1(1, 1.0, 0.5, 1.0);
        assert!(matches!(
            ShellSection::pshell(&PshellSection::homogeneous(m, 1.0)),
            Err(SectionError::Poisson { .. })
        ));
        let ok = PshellSection::homogeneous(RoleMaterial::mat1(1, 1.0, 0.3, 1.0), 1.0);
        assert!(matches!(
            ShellSection::pshell(&PshellSection { t: 0.0, ..ok }),
            Err(SectionError::NonPositive { .. })
        ));
        assert!(matches!(
            ShellSection::pshell(&PshellSection {
                bending_ratio: 0.0,
                ..ok
            }),
            Err(SectionError::NonPositive { .. })
        ));
        for bad in [
            PshellSection {
                membrane: None,
                bending: None,
                shear: None,
                ..ok
            },
            PshellSection {
                bending: None,
                ..ok
            },
            PshellSection {
                bending: None,
                shear: None,
                zoffs: 0.1,
                ..ok
            },
            PshellSection {
                membrane: None,
                zoffs: 0.1,
                ..ok
            },
            PshellSection {
                membrane: None,
                coupling: Some(RoleMaterial::mat1(4, 1.0, 0.3, 1.0)),
                ..ok
            },
        ] {
            assert!(
                matches!(ShellSection::pshell(&bad), Err(SectionError::Roles(_))),
                "{bad:?}"
            );
        }
        // E and NU need a MAT1 target; THETA and TPLY do not apply to a PSHELL.
        let orth = PshellSection::homogeneous(mat8(8), 1e-3);
        for (section, target, param) in [
            (orth, 8, SectionParameter::E),
            (orth, 8, SectionParameter::Nu),
            (ok, 1, SectionParameter::Theta),
            (ok, 1, SectionParameter::Tply),
        ] {
            assert!(matches!(
                affine_sections(
                    &SectionData::Pshell {
                        section,
                        parametrized: target
                    },
                    param
                ),
                Err(SectionError::UnsupportedParameter { .. })
            ));
        }
        let lam = Laminate {
            plies: vec![],
            z0: None,
            nsm: 0.0,
            symmetric: false,
        };
        assert_eq!(ShellSection::laminate(&lam), Err(SectionError::NoPlies));
        let lam = Laminate {
            plies: vec![
                ply(0.0),
                Ply {
                    t: 1e-3,
                    ..ply(0.0)
                },
            ],
            z0: None,
            nsm: 0.0,
            symmetric: false,
        };
        assert!(matches!(
            affine_sections(&SectionData::Laminate(lam), SectionParameter::Tply),
            Err(SectionError::NotUniform { ply: 2, .. })
        ));
    }

    /// Deterministic pseudo-random numbers in [0, 1) (xorshift).
    fn rand(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A PSHELL with distinct MID1 (= MID3), MID2 and MID4 materials, 12I/T³ ≠ 1, TS/T ≠ 5/6,
    /// NSM and an offset; `kirchhoff` leaves MID3 blank (penalty ∝ the MID2 constants).
    fn mixed_pshell(kirchhoff: bool) -> PshellSection {
        let m1 = RoleMaterial::mat1(1, 70e9, 0.33, 2700.0);
        PshellSection {
            t: 3e-3,
            membrane: Some(m1),
            bending: Some(RoleMaterial::mat1(2, 200e9, 0.28, 7800.0)),
            bending_ratio: 0.6,
            shear: (!kirchhoff).then_some(m1),
            shear_ratio: 0.8,
            coupling: Some(RoleMaterial::mat1(4, 5e9, 0.2, 100.0)),
            nsm: 0.7,
            zoffs: 4e-4,
        }
    }

    /// `p` with every role of material `mid` given E, ν, ρ.
    fn with_mat1(p: &PshellSection, mid: u32, e: f64, nu: f64, rho: f64) -> PshellSection {
        let swap = |r: Option<RoleMaterial>| {
            r.map(|m| {
                if m.mid == mid {
                    RoleMaterial::mat1(mid, e, nu, rho)
                } else {
                    m
                }
            })
        };
        PshellSection {
            membrane: swap(p.membrane),
            bending: swap(p.bending),
            shear: swap(p.shear),
            coupling: swap(p.coupling),
            ..*p
        }
    }

    /// Nominal (E, ν, ρ) of material `mid` in `p`.
    fn mat1_of(p: &PshellSection, mid: u32) -> (f64, f64, f64) {
        let roles = [p.membrane, p.bending, p.shear, p.coupling];
        let m = roles.iter().flatten().find(|m| m.mid == mid).unwrap();
        match m.material {
            ShellMaterial::Isotropic { e, nu } => (e, nu, m.rho),
            ShellMaterial::Orthotropic { .. } | ShellMaterial::Anisotropic { .. } => {
                unreachable!("mat1 only")
            }
        }
    }

    fn angle_ply(theta: f64, t: f64, rho: f64, z0: Option<f64>) -> Laminate {
        let mut plies: Vec<Ply> = [1.0, -1.0, 1.0, -1.0, -1.0]
            .iter()
            .map(|&s| Ply {
                t,
                rho,
                ..ply(s * theta)
            })
            .collect();
        plies[4].g1z = None;
        Laminate {
            plies,
            z0,
            nsm: 0.2,
            symmetric: false,
        }
    }

    /// E on the MID2 material scales D only; with MID3 blank also the Kirchhoff penalty (∝ G2).
    /// E on the MID1 = MID3 material scales A, the offset terms z₀A, z₀²A, S and the drill.
    #[test]
    fn parameter_scales_only_the_roles_of_its_material() {
        for kirchhoff in [false, true] {
            let p = mixed_pshell(kirchhoff);
            let split = |mid| {
                let data = SectionData::Pshell {
                    section: p,
                    parametrized: mid,
                };
                affine_sections(&data, SectionParameter::E).unwrap()
            };
            let e2 = split(2)[0].1;
            assert_eq!(split(2)[0].0, Coefficient::E);
            assert_eq!((e2.a, e2.b, e2.drill), ([[0.0; 3]; 3], [[0.0; 3]; 3], 0.0));
            assert!(e2.mass.is_zero() && e2.d[0][0] > 0.0);
            assert_eq!(e2.s[0][0] > 0.0, kirchhoff);
            let e1 = split(1)[0].1;
            let z0 = p.zoffs;
            assert!(e1.a[0][0] > 0.0 && e1.drill > 0.0);
            assert!((e1.b[0][0] - z0 * e1.a[0][0]).abs() <= 1e-15 * e1.a[0][0]);
            assert!((e1.d[0][0] - z0 * z0 * e1.a[0][0]).abs() <= 1e-15 * e1.a[0][0]);
            assert_eq!(e1.s[0][0] > 0.0, !kirchhoff);
            // RHO on a material that is not the mass material (MID1): nothing to split.
            let data = SectionData::Pshell {
                section: p,
                parametrized: 2,
            };
            let rho2 = affine_sections(&data, SectionParameter::Rho).unwrap();
            assert_eq!(rho2.len(), 1);
            assert_eq!(rho2[0].0, Coefficient::Constant);
        }
    }

    #[test]
    fn affine_sections_reproduce_direct_sections() {
        let mut st = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..3 {
            let v = CoefficientValues {
                e: 1e9 + 1e11 * rand(&mut st),
                nu: 0.45 * rand(&mut st),
                rho: 500.0 + 5000.0 * rand(&mut st),
                theta_deg: 90.0 * rand(&mut st),
                h: 1e-4 + 1e-3 * rand(&mut st),
                lumped: 0.0,
            };
            for nominal in [mixed_pshell(false), mixed_pshell(true)] {
                for mid in [1, 2, 4] {
                    let (e0, nu0, rho0) = mat1_of(&nominal, mid);
                    for (param, direct) in [
                        (
                            SectionParameter::E,
                            with_mat1(&nominal, mid, v.e, nu0, rho0),
                        ),
                        (
                            SectionParameter::Nu,
                            with_mat1(&nominal, mid, v.e, v.nu, rho0),
                        ),
                        (
                            SectionParameter::Rho,
                            with_mat1(&nominal, mid, e0, nu0, v.rho),
                        ),
                    ] {
                        let data = SectionData::Pshell {
                            section: nominal,
                            parametrized: mid,
                        };
                        let parts = affine_sections(&data, param).unwrap();
                        let v = if param == SectionParameter::E {
                            CoefficientValues { nu: nu0, ..v }
                        } else {
                            v
                        };
                        let got = evaluate(&parts, &v);
                        let want = ShellSection::pshell(&direct).unwrap();
                        assert!(
                            sections_close(&got, &want, 1e-13),
                            "material {mid} {param:?}\n{got:?}\n{want:?}"
                        );
                    }
                }
            }
            let base = angle_ply(20.0, 0.125e-3, 1600.0, None);
            for (param, direct) in [
                (
                    SectionParameter::Theta,
                    angle_ply(v.theta_deg, 0.125e-3, 1600.0, None),
                ),
                (SectionParameter::Tply, angle_ply(20.0, v.h, 1600.0, None)),
                (
                    SectionParameter::Rho,
                    angle_ply(20.0, 0.125e-3, v.rho, None),
                ),
            ] {
                let parts = affine_sections(&SectionData::Laminate(base.clone()), param).unwrap();
                let got = evaluate(&parts, &v);
                let want = ShellSection::laminate(&direct).unwrap();
                assert!(
                    sections_close(&got, &want, 1e-12),
                    "{param:?}\n{got:?}\n{want:?}"
                );
            }
            // Explicit Z0 scales with h under TPLY.
            let base = angle_ply(20.0, 0.125e-3, 1600.0, Some(-0.2e-3));
            let parts =
                affine_sections(&SectionData::Laminate(base), SectionParameter::Tply).unwrap();
            let want = ShellSection::laminate(&angle_ply(
                20.0,
                v.h,
                1600.0,
                Some(-0.2e-3 * v.h / 0.125e-3),
            ))
            .unwrap();
            assert!(sections_close(&evaluate(&parts, &v), &want, 1e-12));
        }
    }

    /// The Θ parts of an angle-ply laminate summed at Θ = 0° and 90°, where the five functions
    /// of eq. 3.18 are 0 or 1 (cos⁴ + sin⁴ + 2cos²sin² = 1 leaves nothing to cancel), equal the
    /// section built directly at that angle: A, B, D, S, drill and mass to 1e-15 of each
    /// matrix's largest entry (a few ulps; cos 90° = 6e-17 instead of 0).
    #[test]
    fn theta_parts_at_zero_and_ninety_degrees_equal_the_direct_sections() {
        let base = angle_ply(20.0, 0.125e-3, 1600.0, None);
        let parts = affine_sections(&SectionData::Laminate(base), SectionParameter::Theta).unwrap();
        for theta_deg in [0.0, 90.0] {
            let v = CoefficientValues {
                theta_deg,
                ..CoefficientValues::default()
            };
            let got = evaluate(&parts, &v);
            let want =
                ShellSection::laminate(&angle_ply(theta_deg, 0.125e-3, 1600.0, None)).unwrap();
            let scale = want.a.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(close3(&got.a, &want.a, 1e-15), "Θ = {theta_deg}: A");
            assert!(close3(&got.d, &want.d, 1e-15), "Θ = {theta_deg}: D");
            assert!(
                got.b
                    .iter()
                    .flatten()
                    .zip(want.b.iter().flatten())
                    .all(|(x, y)| (x - y).abs() <= 1e-15 * scale * 0.125e-3),
                "Θ = {theta_deg}: B"
            );
            let s_scale = want.s.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(
                got.s
                    .iter()
                    .flatten()
                    .zip(want.s.iter().flatten())
                    .all(|(x, y)| (x - y).abs() <= 1e-15 * s_scale),
                "Θ = {theta_deg}: S"
            );
            assert!((got.drill - want.drill).abs() <= 1e-15 * want.drill);
            assert_eq!(got.mass, want.mass);
        }
    }
}
