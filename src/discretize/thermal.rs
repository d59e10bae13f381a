//! Thermal loads (`TEMPERATURE(LOAD)`, SOL 101) and the thermal strains stress recovery
//! subtracts.
//!
//! **Element temperature.** Each element takes one temperature, the mean of its grids'
//! temperatures in the set ([`Model::grid_temperatures`]: TEMP, else the set's TEMPD), and
//! ΔT = T − TREF with the TREF of its material (MAT1, MAT8, MAT2; the PCOMP's TREF for every ply
//! of a laminate, as Nastran's PCOMP). Through-thickness gradients (TEMPP1) and beam section
//! gradients (TEMPRB) are not read (those cards are refused as unsupported).
//!
//! **Free thermal deformation.** ΔT strains an unrestrained element by
//! - MAT1 solids, rods, beams and PSHELLs whose membrane material (MID1) is a MAT1: the
//!   homogeneous expansion u = αΔT (x − c), θ = 0 (c: the mean of the element's points; a rod or
//!   beam takes x at its offset ends, so the rigid offsets do not expand);
//! - PSHELL with a MAT8 or MAT2 MID1: the membrane strain ε⁰ = {α1 α2 α12}ΔT in the element
//!   material axes, no curvature;
//! - PCOMP: (ε⁰, κ) = [A B; B D]⁻¹ (N_T, M_T) with the thermal resultants of
//!   [`laminate::thermal_resultants`] (each ply's {α1 α2 0}ΔT in its axes), i.e. the free
//!   laminate's warping by its unsymmetric plies;
//!
//! and u_free is the displacement field with those constant strains (in the material axes x, y
//! about the element centre: u = εx x + ½γxy y, v = ½γxy x + εy y, w = −½(κx x² + κy y² +
//! κxy xy), θx = −κy y − ½κxy x, θy = κx x + ½κxy y, θz = 0; [`crate::fe::shell`] signs).
//!
//! **Equivalent load.** The consistent nodal load of the thermal strain is f = ∫Bᵀ C ε_th dV.
//! Every element here reproduces a constant strain (and the shells a constant curvature)
//! exactly — the patch test: B u_free = ε_th at every integration point, with the CQUAD4's
//! condensed incompatible modes silent since ∫B_i dA = 0 and the MITC shear strains zero on a
//! field without transverse shear — so f = K_e u_free, K_e the element stiffness at the nominal
//! parameters. The loads are added in each grid's global frame like the element matrices. (A
//! curved CQUAD8/CTRIA6 is the exception: its director does not stretch, so the homothety's
//! through-thickness part is missing, a bending strain of order αΔT·t/R.)
//!
//! **Recovery.** Stresses are C (ε − ε_th): shell forces from (ε⁰ − ε⁰_free, κ − κ_free), ply
//! stresses Q (ε − {α1 α2 0}ΔT) in the ply axes, solid stresses with αΔT off the normal
//! strains. Reported strains are total strains, as Nastran's element strains.

use std::collections::HashMap;

use faer::linalg::solvers::Solve;

use super::elements::{ShellRecovery, element_stiffnesses};
use super::{DiscretizeError, Structure};
use crate::assembly::DofMap;
use crate::fe::laminate::{Laminate, ShellSection, thermal_resultants};
use crate::fe::shell::ShellStrains;
use crate::geometry::vec3::{cross, dot, norm, scale, sub};
use crate::model::materials::Material;
use crate::model::properties::{LaminateProperty, ShellProperty};
use crate::model::{Element, Model};

use super::elements::{CentreSection, shell_centre_section};

/// Grid temperatures by grid index (`None`: the set gives the grid none).
pub type GridTemperatures = [Option<f64>];

/// The free thermal strains of a shell in its material system.
#[derive(Debug, Clone, PartialEq)]
pub struct ShellThermal {
    /// Reference-plane strains ε⁰ = [εx, εy, γxy] of the free element.
    pub membrane: [f64; 3],
    /// Curvatures κ of the free element.
    pub curvature: [f64; 3],
    /// Each ply's thermal strain {α1 α2 0}ΔT in its own axes (PCOMP; empty for PSHELL).
    pub plies: Vec<[f64; 3]>,
}

/// The free thermal deformation of one element.
#[derive(Debug, Clone, PartialEq)]
pub enum FreeStrain {
    /// Homogeneous expansion by the strain αΔT in every direction.
    Isotropic(f64),
    /// A shell's free strains in its material axes (orthotropic or laminated sections).
    Shell(ShellThermal),
}

fn err(e: &Element, reason: impl ToString) -> DiscretizeError {
    DiscretizeError::Element {
        card: e.kind.card(),
        id: e.id,
        reason: reason.to_string(),
    }
}

/// The mean temperature of the element's grids; an error naming a grid without one.
fn element_temperature(
    model: &Model,
    e: &Element,
    temps: &GridTemperatures,
    sid: u32,
) -> Result<f64, DiscretizeError> {
    let mut sum = 0.0;
    for &a in &e.nodes {
        match temps.get(a).copied().flatten() {
            Some(t) => sum += t,
            None => {
                let id = model.grids.get(a).map_or(0, |g| g.id);
                return Err(err(
                    e,
                    format!(
                        "GRID {id} has no temperature in temperature set {sid} (no TEMP for it and no TEMPD {sid})"
                    ),
                ));
            }
        }
    }
    Ok(sum / e.nodes.len() as f64)
}

/// The thermal expansion of `mid` as ΔT-scaled strains, `None` when it has none.
fn thermal_strain(
    model: &Model,
    e: &Element,
    mid: u32,
    t: f64,
    tref: Option<f64>,
) -> Result<Option<[f64; 3]>, DiscretizeError> {
    let x = model
        .expansion(mid)
        .ok_or_else(|| err(e, format!("material {mid} missing")))?;
    let dt = t - tref.unwrap_or(x.tref);
    Ok((x.alpha.iter().any(|&a| a != 0.0) && dt != 0.0).then(|| x.alpha.map(|a| a * dt)))
}

/// The free thermal deformation of `e` in temperature set `sid`, `None` when it has none
/// (no expansion coefficient, ΔT = 0, or an element without thermal strain: springs, dampers,
/// bushings, masses, shear panels).
pub fn free_strain(
    model: &Model,
    e: &Element,
    temps: &GridTemperatures,
    sid: u32,
) -> Result<Option<FreeStrain>, DiscretizeError> {
    let isotropic = |mid: u32, t: f64| -> Result<Option<FreeStrain>, DiscretizeError> {
        Ok(match thermal_strain(model, e, mid, t, None)? {
            Some([a1, a2, a12]) if a1 == a2 && a12 == 0.0 => Some(FreeStrain::Isotropic(a1)),
            Some(_) => {
                return Err(err(
                    e,
                    format!("MID = {mid}: a rod, beam or solid needs a MAT1 for its thermal load"),
                ));
            }
            None => None,
        })
    };
    // the element's temperature, asked for only when its material expands (a set may leave the
    // grids of non-expanding elements without temperatures)
    let temperature = || element_temperature(model, e, temps, sid);
    let expands = |mid: u32| {
        model
            .expansion(mid)
            .is_some_and(|x| x.alpha.iter().any(|&a| a != 0.0))
    };
    if e.kind.is_line() {
        let (_, used) = model
            .line_element(e)
            .ok_or_else(|| err(e, "not a line element"))?
            .map_err(|x| err(e, x))?;
        if !expands(used.mid) {
            return Ok(None);
        }
        return isotropic(used.mid, temperature()?);
    }
    if let Some(bend) = model.bend_element(e) {
        let (_, used) = bend.map_err(|x| err(e, x))?;
        if expands(used.mid) {
            return Err(err(
                e,
                "thermal loads on a CBEND are not supported (its MAT1 has A ≠ 0)",
            ));
        }
        return Ok(None);
    }
    if let Some((_, used)) = model
        .solid_midsides(e)
        .and(e.property)
        .and_then(|p| model.solid_material(p))
    {
        if !expands(used.mid) {
            return Ok(None);
        }
        return isotropic(used.mid, temperature()?);
    }
    if !e.kind.is_shell() {
        return Ok(None);
    }
    match shell_centre_section(model, e)? {
        CentreSection::Pshell(p) => {
            let Some(role) = p.membrane.filter(|r| expands(r.mid)) else {
                return Ok(None);
            };
            Ok(
                match thermal_strain(model, e, role.mid, temperature()?, None)? {
                    None => None,
                    Some([a1, a2, a12]) if a1 == a2 && a12 == 0.0 => {
                        Some(FreeStrain::Isotropic(a1))
                    }
                    Some(membrane) => Some(FreeStrain::Shell(ShellThermal {
                        membrane,
                        curvature: [0.0; 3],
                        plies: Vec::new(),
                    })),
                },
            )
        }
        CentreSection::Laminate(l) => {
            let Some(ShellProperty::Laminate(p)) = e.property.and_then(|p| model.shell_property(p))
            else {
                return Err(err(e, "PCOMP missing"));
            };
            if !p.plies.iter().any(|ply| expands(ply.material.mid)) {
                return Ok(None);
            }
            laminate_free_strain(model, e, (&l, &p), temperature()?)
        }
    }
}

/// A PCOMP's free strains at temperature `t`: (ε⁰, κ) = ABD⁻¹ (N_T, M_T), `l` its section and
/// `p` its card's plies and TREF.
fn laminate_free_strain(
    model: &Model,
    e: &Element,
    (l, p): (&Laminate, &LaminateProperty),
    t: f64,
) -> Result<Option<FreeStrain>, DiscretizeError> {
    let mut plies = Vec::with_capacity(p.plies.len());
    for ply in &p.plies {
        if matches!(ply.material.material, Some(Material::Anisotropic(_))) {
            return Err(err(e, "a PCOMP ply needs a MAT8 or MAT1"));
        }
        let strain = thermal_strain(model, e, ply.material.mid, t, Some(p.tref))?;
        plies.push(strain.map_or([0.0; 3], |[a1, a2, _]| [a1, a2, 0.0]));
    }
    if plies.iter().all(|s| *s == [0.0; 3]) {
        return Ok(None);
    }
    let (n, m) = thermal_resultants(l, &plies).map_err(|x| err(e, x))?;
    let section = ShellSection::laminate(l).map_err(|x| err(e, x))?;
    let mut abd = faer::Mat::<f64>::zeros(6, 6);
    for i in 0..3 {
        for j in 0..3 {
            abd[(i, j)] = section.a[i][j];
            abd[(i, 3 + j)] = section.b[i][j];
            abd[(3 + i, j)] = section.b[i][j];
            abd[(3 + i, 3 + j)] = section.d[i][j];
        }
    }
    let mut rhs = faer::Mat::<f64>::zeros(6, 1);
    for i in 0..3 {
        rhs[(i, 0)] = n[i];
        rhs[(3 + i, 0)] = m[i];
    }
    let free = abd.partial_piv_lu().solve(&rhs);
    if (0..6).any(|i| !free[(i, 0)].is_finite()) {
        return Err(err(e, "the laminate's [A B; B D] is singular"));
    }
    Ok(Some(FreeStrain::Shell(ShellThermal {
        membrane: std::array::from_fn(|i| free[(i, 0)]),
        curvature: std::array::from_fn(|i| free[(3 + i, 0)]),
        plies,
    })))
}

/// The material axes (x_m, y_m, n) and centre of a flat 3- or 4-node shell, as
/// [`crate::fe::shell`] builds them: n from the diagonals (quad) or two edges (triangle), x_m
/// the material direction (G1→G2 by default) projected on the plane.
fn shell_axes(
    e: &Element,
    xyz: &[[f64; 3]],
    rec: &ShellRecovery,
) -> Result<([[f64; 3]; 3], [f64; 3]), DiscretizeError> {
    let normal = match xyz.len() {
        4 => cross(sub(xyz[2], xyz[0]), sub(xyz[3], xyz[1])),
        3 => cross(sub(xyz[1], xyz[0]), sub(xyz[2], xyz[0])),
        _ => {
            return Err(err(
                e,
                "a thermal load on a CQUAD8 / CTRIA6 needs an isotropic membrane (PSHELL with a MAT1 MID1)",
            ));
        }
    };
    let n = scale(normal, 1.0 / norm(normal));
    let mx = rec.material_x.unwrap_or_else(|| sub(xyz[1], xyz[0]));
    let proj = sub(mx, scale(n, dot(mx, n)));
    let x = scale(proj, 1.0 / norm(proj));
    Ok(([x, cross(n, x), n], centre(xyz)))
}

fn centre(xyz: &[[f64; 3]]) -> [f64; 3] {
    let k = xyz.len() as f64;
    std::array::from_fn(|i| xyz.iter().map(|p| p[i]).sum::<f64>() / k)
}

/// The free displacement and rotation (basic) of each of the element's grids.
fn free_field(
    model: &Model,
    shells: &HashMap<usize, &ShellRecovery>,
    e: &Element,
    free: &FreeStrain,
) -> Result<Vec<[f64; 6]>, DiscretizeError> {
    let mut xyz = model.positions(e);
    if e.kind.is_line()
        && let Some(Ok((line, _))) = model.line_element(e)
    {
        for (p, off) in xyz.iter_mut().zip(line.offsets) {
            *p = std::array::from_fn(|i| p[i] + off[i]);
        }
    }
    match free {
        FreeStrain::Isotropic(strain) => {
            let c = centre(&xyz);
            Ok(xyz
                .iter()
                .map(|p| {
                    let mut r = [0.0; 6];
                    (0..3).for_each(|i| r[i] = strain * (p[i] - c[i]));
                    r
                })
                .collect())
        }
        FreeStrain::Shell(s) => {
            let rec = model
                .element_index
                .get(&e.id)
                .and_then(|i| shells.get(i))
                .ok_or_else(|| err(e, "shell recovery data missing"))?;
            let ([ax, ay, n], c) = shell_axes(e, &xyz, rec)?;
            let ([ex, ey, g], [kx, ky, kxy]) = (s.membrane, s.curvature);
            Ok(xyz
                .iter()
                .map(|p| {
                    let d = sub(*p, c);
                    let (x, y) = (dot(d, ax), dot(d, ay));
                    let u = ex * x + 0.5 * g * y;
                    let v = 0.5 * g * x + ey * y;
                    let w = -0.5 * (kx * x * x + ky * y * y + kxy * x * y);
                    let tx = -ky * y - 0.5 * kxy * x;
                    let ty = kx * x + 0.5 * kxy * y;
                    std::array::from_fn(|i| {
                        if i < 3 {
                            u * ax[i] + v * ay[i] + w * n[i]
                        } else {
                            tx * ax[i - 3] + ty * ay[i - 3]
                        }
                    })
                })
                .collect())
        }
    }
}

/// The free thermal deformation of every element in one temperature set, by element id.
#[derive(Debug, Clone, Default)]
pub struct ThermalStrains {
    by_element: HashMap<u32, FreeStrain>,
}

impl ThermalStrains {
    /// The elements' free deformations in temperature set `sid` (TEMP / TEMPD).
    pub fn of_set(model: &Model, sid: u32) -> Result<Self, DiscretizeError> {
        let temps = model
            .grid_temperatures(sid)
            .ok_or_else(|| DiscretizeError::Element {
                card: "TEMPERATURE(LOAD)",
                id: sid,
                reason: format!("no TEMP or TEMPD set {sid}"),
            })?;
        let mut by_element = HashMap::new();
        for e in &model.elements {
            if let Some(f) = free_strain(model, e, &temps, sid)? {
                by_element.insert(e.id, f);
            }
        }
        Ok(ThermalStrains { by_element })
    }

    /// The free deformation of element `eid`, `None` when it has none.
    pub fn get(&self, eid: u32) -> Option<&FreeStrain> {
        self.by_element.get(&eid)
    }

    /// `strains` less the free thermal strains of shell `eid` (reference plane and
    /// curvature; the transverse shear has none): what the section's forces follow.
    pub fn shell_mechanical(&self, eid: u32, strains: &ShellStrains) -> ShellStrains {
        let (membrane, curvature) = match self.get(eid) {
            None => return *strains,
            Some(FreeStrain::Isotropic(a)) => ([*a, *a, 0.0], [0.0; 3]),
            Some(FreeStrain::Shell(s)) => (s.membrane, s.curvature),
        };
        ShellStrains {
            membrane: std::array::from_fn(|i| strains.membrane[i] - membrane[i]),
            curvature: std::array::from_fn(|i| strains.curvature[i] - curvature[i]),
            ..*strains
        }
    }

    /// The plies' thermal strains of laminate `eid` in their axes (empty without).
    pub fn plies(&self, eid: u32) -> &[[f64; 3]] {
        match self.get(eid) {
            Some(FreeStrain::Shell(s)) => &s.plies,
            _ => &[],
        }
    }

    /// `strain` [εxx εyy εzz γxy γyz γzx] of solid `eid` less its thermal strain αΔT.
    pub fn solid_mechanical(&self, eid: u32, strain: &[f64; 6]) -> [f64; 6] {
        match self.get(eid) {
            Some(FreeStrain::Isotropic(a)) => {
                std::array::from_fn(|i| if i < 3 { strain[i] - a } else { strain[i] })
            }
            _ => *strain,
        }
    }
}

/// P_g (global frames) of the thermal load of `strains`: Σ_e K_e u_free,e over the elements
/// with a free thermal deformation (module doc).
pub fn thermal_load(
    model: &Model,
    st: &Structure,
    strains: &ThermalStrains,
) -> Result<Vec<f64>, DiscretizeError> {
    let free = &strains.by_element;
    let mut p = vec![0.0; st.map.size()];
    let nominal = st.params.nominal();
    let keep = |e: &Element| free.contains_key(&e.id);
    let shells: HashMap<usize, &ShellRecovery> = st.shells.iter().map(|(i, r)| (*i, r)).collect();
    for (e, k) in element_stiffnesses(model, &st.frames, &st.params, keep)? {
        let field = free_field(model, &shells, e, &free[&e.id])?;
        // the free field in each grid's global frame, by g index, on the contribution's DOFs
        let mut global = HashMap::new();
        for (&a, r) in e.nodes.iter().zip(&field) {
            let t = st.frames.to_global(a, [r[0], r[1], r[2]]);
            let q = st.frames.to_global(a, [r[3], r[4], r[5]]);
            for (c, v) in t.into_iter().chain(q).enumerate() {
                global.insert(DofMap::dof(a, c), v);
            }
        }
        let u: Vec<f64> = k
            .dofs
            .iter()
            .map(|d| global.get(d).copied().unwrap_or(0.0))
            .collect();
        for (key, part) in &k.parts {
            let w = st.params.function(*key).value(&nominal);
            for (r, &row) in k.dofs.iter().enumerate() {
                let f: f64 = (0..u.len()).map(|c| part[(r, c)] * u[c]).sum();
                p[row] += w * f;
            }
        }
    }
    Ok(p)
}
