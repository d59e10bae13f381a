//! CSHEAR + PSHEAR + MAT1 → [`ShearPanel`] matrices, split by the PMPARs acting on the MAT1.
//!
//! K = G·t·K₁ (K₁ = [`ShearPanel::unit_stiffness`]): constant at the card's G, ∝ E with
//! G/E fixed under `PMPAR E`, ∝ μ = E/(2(1+ν)) under `PMPAR NU` (which needs G blank on the
//! MAT1, so that G follows E and ν). M = (ρt + NSM)·M₁: the ρt part ∝ ρ under `PMPAR RHO`.

use super::{Built, ElementContext, err, isotropic_built};
use crate::assembly::ParamTarget;
use crate::card_values::PmparKind;
use crate::discretize::DiscretizeError;
use crate::fe::affine::{AffineMatrix, Coefficient};
use crate::fe::shear_panel::ShearPanel;
use crate::model::Element;
use crate::model::materials::Material;

/// The panel's thickness, non-structural mass, MAT1 id and geometry.
pub(crate) fn panel(
    model: &crate::model::Model,
    e: &Element,
) -> Result<(ShearPanel, f64, f64, u32), DiscretizeError> {
    let p = model.pshear(e).ok_or_else(|| err(e, "PSHEAR missing"))?;
    let xyz: [[f64; 3]; 4] = model
        .positions(e)
        .try_into()
        .map_err(|_| err(e, "a CSHEAR has 4 grids"))?;
    let panel = ShearPanel::new(&xyz).map_err(|x| err(e, x))?;
    Ok((panel, p.t, p.nsm, p.mid))
}

pub(super) fn shear_panel_element(
    ctx: &ElementContext,
    e: &Element,
) -> Result<Built, DiscretizeError> {
    let (panel, t, nsm, mid) = panel(ctx.model, e)?;
    let m = match ctx.model.material(mid) {
        Some(Material::Isotropic(m)) => m,
        Some(other) => {
            return Err(err(
                e,
                format!("MID = {mid} is a {}; a PSHEAR needs a MAT1", other.card()),
            ));
        }
        None => return Err(err(e, format!("material {mid} missing"))),
    };
    let target = ParamTarget::Material(mid);
    let kinds = ctx.params.kinds_on(target);
    let unit = panel.unit_stiffness();
    let stiffness = if kinds.contains(&PmparKind::Nu) {
        let derived = m.e / (2.0 * (1.0 + m.nu));
        if (m.g - derived).abs() > 1e-9 * derived.abs() {
            return Err(err(
                e,
                format!(
                    "PMPAR NU on MAT1 {mid}: its G = {:e} is not E/(2(1+NU)) = {derived:e}, so the panel's shear stiffness would not follow NU; leave G blank on the MAT1",
                    m.g
                ),
            ));
        }
        (Coefficient::Mu, &unit * faer::Scale(t))
    } else if kinds.contains(&PmparKind::E) {
        (Coefficient::E, &unit * faer::Scale(t * m.g / m.e))
    } else {
        (Coefficient::Constant, &unit * faer::Scale(t * m.g))
    };
    let unit_mass = panel.unit_mass(ctx.lumped);
    let mut mass = vec![(Coefficient::Constant, &unit_mass * faer::Scale(nsm))];
    if kinds.contains(&PmparKind::Rho) {
        mass.push((Coefficient::Rho, &unit_mass * faer::Scale(t)));
    } else {
        mass[0].1 = &unit_mass * faer::Scale(nsm + m.rho * t);
    }
    let k = AffineMatrix {
        parts: vec![stiffness],
    };
    let mass = AffineMatrix { parts: mass };
    Ok(isotropic_built(
        ctx,
        e,
        target,
        &m,
        (&k, &mass),
        m.rho * t + nsm != 0.0,
    ))
}
