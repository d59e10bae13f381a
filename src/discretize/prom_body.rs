//! A flexible body from a pROM artifact built with `RIGID = REMOVE` at parameters p (thesis
//! §4.2): the reduced M_ff(p), K_ff(p), C_ff(p) of the pROM (eq. 3.31), the mass invariants
//! combined at p from their affine components (eq. 4.8, M̂(p) = Σₖ fₖ(p) M̂ᵏ) and the basis rows
//! of the interface grids with their undeformed positions, and the rows C_ε over the reduced
//! basis of the artifact's STRAIN sensors (`/prom/sensors`, eq. 2.57: ε = C_ε q_f, the rigid
//! motion carried by the frame strains nothing). Only small dense sums: no FOM.
//!
//! [`ParametricBody`] is what a body needs to be evaluated at any p (read once from the
//! artifact, or from a pFMB artifact's `/pfmb/bodies`); [`ParametricBody::at`] evaluates it.

use std::path::Path;

use super::sensors::sensor_kind_name;
use crate::card_values::SensorKind;
use crate::io::{read_prom, read_prom_body, read_prom_sensors};
use crate::multibody::{FlexibleBodyData, InterfaceRows, MassInvariants};
use crate::rom::invariants::MassInvariants as AffineInvariants;
use crate::rom::prom::Prom;

/// A flexible body's data at one parameter point, with the point.
#[derive(Debug, Clone)]
pub struct PromBodyAtPoint {
    pub data: FlexibleBodyData,
    /// The pROM's parameter names and the values used (nominal where not given).
    pub parameters: Vec<(String, f64)>,
    /// Names of the parameters outside the box the pROM was built for.
    pub extrapolated: Vec<String>,
    /// The artifact's STRAIN sensors: name and row C_ε (one value per flexible coordinate).
    pub strain_sensors: Vec<(String, Vec<f64>)>,
}

/// A flexible body as a function of its pROM's parameters: the pROM (affine K, M, damping,
/// parameters with their boxes), the affine components of the mass invariants in the pROM's
/// function order (eq. 4.8), the interface grids' rows and positions and the STRAIN sensors'
/// rows (neither depends on p: the basis is constant).
#[derive(Debug, Clone)]
pub struct ParametricBody {
    pub prom: Prom,
    pub invariants: Vec<AffineInvariants>,
    pub interfaces: Vec<InterfaceRows>,
    pub strain_sensors: Vec<(String, Vec<f64>)>,
}

/// Reads the artifact at `path` and evaluates it at the nominal parameters overridden by
/// `values` (PMPAR name, value; case-insensitive). Errors are messages naming the file.
pub fn load_prom_body(path: &Path, values: &[(String, f64)]) -> Result<PromBodyAtPoint, String> {
    read_parametric_body(path)?.at(values, &path.display().to_string())
}

/// Reads what a multibody body needs from the `RIGID = REMOVE` artifact at `path`.
pub fn read_parametric_body(path: &Path) -> Result<ParametricBody, String> {
    let shown = path.display();
    let (prom, _) = read_prom(path).map_err(|e| e.to_string())?;
    let n = prom.size();
    let body = read_prom_body(path, n, prom.functions.len())
        .map_err(|e| e.to_string())?
        .ok_or_else(|| {
            format!(
                "{shown} has no multibody data (/prom/nodal_mass): it was built with RIGID = KEEP; rebuild it with PMOR RIGID = REMOVE"
            )
        })?;
    let interfaces =
        body.interface
            .grids
            .iter()
            .zip(&body.interface.rows)
            .map(|(&grid, rows)| {
                let index = body.grids.iter().position(|&g| g == grid).ok_or_else(|| {
                    format!("{shown}: interface grid {grid} has no nodal position")
                })?;
                let row = |c: usize| {
                    (0..n)
                        .map(|k| std::array::from_fn(|a| rows[(c + a, k)]))
                        .collect()
                };
                Ok(InterfaceRows {
                    grid,
                    position: body.masses.positions[index],
                    translation: row(0),
                    rotation: row(3),
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
    let (names, kinds, rows) = read_prom_sensors(path, n).map_err(|e| e.to_string())?;
    let strain_sensors = names
        .into_iter()
        .zip(&kinds)
        .enumerate()
        .filter(|(_, (_, kind))| kind.as_str() == sensor_kind_name(SensorKind::Strain))
        .map(|(i, (name, _))| (name, (0..n).map(|k| rows[(i, k)]).collect()))
        .collect();
    Ok(ParametricBody {
        prom,
        invariants: body.invariants,
        interfaces,
        strain_sensors,
    })
}

impl ParametricBody {
    /// ∂D/∂pⱼ of the body's data D at the nominal parameters overridden by `values` (see
    /// [`ParametricBody::parameter_vector`]): ∂M_ff, ∂K_ff, ∂C_ff = α ∂M_ff + β ∂K_ff of the
    /// pROM (eq. 3.32) and the invariants' derivative Σᵢ ∂fᵢ/∂pⱼ M̂ⁱ (eq. 4.8), with the (constant)
    /// interface rows. What [`crate::multibody::System::eom_terms_rate`] takes.
    pub fn derivative(
        &self,
        values: &[(String, f64)],
        j: usize,
        shown: &str,
    ) -> Result<FlexibleBodyData, String> {
        let prom = &self.prom;
        let p = self.parameter_vector(values, shown)?;
        let mut at = prom.workspace();
        prom.evaluate(&p, &mut at)
            .map_err(|e| format!("{shown}: {e}"))?;
        let rates: Vec<f64> = prom.functions.iter().map(|f| f.derivative(&p, j)).collect();
        let invariants = AffineInvariants::combine(&self.invariants, &rates)
            .ok_or_else(|| format!("{shown}: no affine mass component"))?;
        let (d_mass, d_stiffness) = (at.d_mass(j).to_owned(), at.d_stiffness(j).to_owned());
        let d_damping = &d_mass * faer::Scale(prom.alpha) + &d_stiffness * faer::Scale(prom.beta);
        Ok(FlexibleBodyData {
            invariants: MassInvariants::from(&invariants),
            mass: d_mass,
            stiffness: d_stiffness,
            damping: d_damping,
            interfaces: self.interfaces.clone(),
        })
    }

    /// The pROM's parameter vector: the nominal values overridden by `values` (PMPAR name,
    /// value; case-insensitive). `shown` names the body's source in errors.
    pub fn parameter_vector(
        &self,
        values: &[(String, f64)],
        shown: &str,
    ) -> Result<Vec<f64>, String> {
        let prom = &self.prom;
        let mut p: Vec<f64> = prom.parameters.iter().map(|q| q.nominal).collect();
        for (name, value) in values {
            let j = prom
                .parameters
                .iter()
                .position(|q| q.name.eq_ignore_ascii_case(name))
                .ok_or_else(|| {
                    format!(
                        "{name} is not a parameter of {shown} (parameters: {})",
                        prom.parameters
                            .iter()
                            .map(|q| q.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                })?;
            p[j] = *value;
        }
        Ok(p)
    }

    /// The body at the nominal parameters overridden by `values` (see
    /// [`ParametricBody::parameter_vector`]).
    pub fn at(&self, values: &[(String, f64)], shown: &str) -> Result<PromBodyAtPoint, String> {
        let prom = &self.prom;
        let p = self.parameter_vector(values, shown)?;
        let mut at = prom.workspace();
        prom.evaluate(&p, &mut at)
            .map_err(|e| format!("{shown}: {e}"))?;
        let weights: Vec<f64> = prom.functions.iter().map(|f| f.value(&p)).collect();
        let invariants = AffineInvariants::combine(&self.invariants, &weights)
            .ok_or_else(|| format!("{shown}: no affine mass component"))?;
        Ok(PromBodyAtPoint {
            data: FlexibleBodyData {
                invariants: MassInvariants::from(&invariants),
                mass: at.mass().to_owned(),
                stiffness: at.stiffness().to_owned(),
                damping: at.damping().to_owned(),
                interfaces: self.interfaces.clone(),
            },
            extrapolated: prom.outside_box(&p).into_iter().map(String::from).collect(),
            strain_sensors: self.strain_sensors.clone(),
            parameters: prom
                .parameters
                .iter()
                .map(|q| q.name.clone())
                .zip(p)
                .collect(),
        })
    }
}
