//! `PLOAD1` cards resolved to grid loads: the element's placement from the model, positions
//! and intensities in the kernel's terms, and the consistent loads of
//! [`crate::fe::beam_load`] at its two grids (for a CBEND, of [`crate::fe::bend::grid_loads`]).

use super::sets::PointLoad;
use super::{ElementKind, Model};
use crate::card_values::{Dofs, ForceKind};
use crate::deck::cards::Pload1;
use crate::fe::beam_load::{LineLoad, LineLoadKind, LoadAxes, grid_loads};

impl Model {
    /// The grid loads of a `PLOAD1` (scaled by `factor`), or what is wrong with it: an element
    /// that is not a CBAR, CBEAM or CBEND, pin flags, positions beyond the element's length.
    pub fn pload1_loads(&self, card: &Pload1, factor: f64) -> Result<Vec<PointLoad>, String> {
        let element = self
            .element_index
            .get(&card.eid)
            .map(|&i| &self.elements[i])
            .filter(|e| {
                matches!(
                    e.kind,
                    ElementKind::Cbar | ElementKind::Cbeam | ElementKind::Cbend
                )
            })
            .ok_or(format!("EID = {} is not a CBAR, CBEAM or CBEND", card.eid))?;
        if element.kind == ElementKind::Cbend {
            return self.pload1_bend_loads(card, element, factor);
        }
        let (line, _) = self.line_element(element).ok_or("not a line element")??;
        if line.pins.iter().any(|p| *p != Dofs::NONE) {
            return Err(format!(
                "{} {} has pin flags (PA/PB): loads along a beam with released ends are not supported",
                element.kind.card(),
                card.eid
            ));
        }
        let geometry = line.geometry();
        let length = crate::fe::beam::length(&geometry).map_err(|e| e.to_string())?;
        let at = fractions_along(card, length, "the element's length")?;
        let mut direction = [0.0; 3];
        direction[card.axis] = 1.0;
        let load = LineLoad {
            kind: match card.kind {
                ForceKind::Force => LineLoadKind::Force,
                ForceKind::Moment => LineLoadKind::Moment,
            },
            direction,
            axes: if card.element_axes {
                LoadAxes::Element
            } else {
                LoadAxes::Basic
            },
            at: at.map(|x| x.min(1.0)),
            values: card.p.map(|p| p * factor),
            projected: card.scale.projected(),
        };
        let loads = grid_loads(&geometry, &load).map_err(|e| e.to_string())?;
        let mut out = Vec::with_capacity(4);
        for (end, &grid) in element.nodes.iter().enumerate() {
            out.push(PointLoad {
                kind: ForceKind::Force,
                grid,
                basic: loads.force[end],
            });
            out.push(PointLoad {
                kind: ForceKind::Moment,
                grid,
                basic: loads.moment[end],
            });
        }
        Ok(out)
    }
}

impl Model {
    /// A `PLOAD1` on a CBEND: positions along the arc (LE: arc length from A, FR: its
    /// fraction), intensities per unit arc length, directions in the basic system; the grid
    /// loads of [`crate::fe::bend::grid_loads`].
    fn pload1_bend_loads(
        &self,
        card: &Pload1,
        element: &super::Element,
        factor: f64,
    ) -> Result<Vec<PointLoad>, String> {
        if card.element_axes {
            return Err(
                "element-axis directions (FXE … MZE) on a CBEND are not supported; give FX … MZ (basic)"
                    .into(),
            );
        }
        if card.scale.projected() {
            return Err("projected intensities (LEPR, FRPR) on a CBEND are not supported".into());
        }
        let (bend, used) = self.bend_element(element).ok_or("not a CBEND")??;
        let Some(super::materials::Material::Isotropic(m)) = used.material else {
            return Err(format!("MID = {} of the CBEND is not a MAT1", used.mid));
        };
        let length = bend.arc.length();
        let at = fractions_along(card, length, "the CBEND's arc length")?;
        let mut direction = [0.0; 3];
        direction[card.axis] = 1.0;
        let load = crate::fe::bend::ArcLoad {
            moment: card.kind == ForceKind::Moment,
            direction,
            at: at.map(|x| x.min(1.0)),
            values: card.p.map(|p| p * factor),
        };
        let loads = crate::fe::bend::grid_loads(&bend.arc, &bend.section, m.e, m.g, &load)
            .map_err(|e| e.to_string())?;
        let mut out = Vec::with_capacity(4);
        for (end, &grid) in element.nodes.iter().enumerate() {
            for (k, kind) in [(0, ForceKind::Force), (3, ForceKind::Moment)] {
                let o = 6 * end + k;
                out.push(PointLoad {
                    kind,
                    grid,
                    basic: [loads[o], loads[o + 1], loads[o + 2]],
                });
            }
        }
        Ok(out)
    }
}

/// Every `PLOAD1` that cannot be resolved, as a deck error at its line. A card on an element
/// whose card exists (`declared`) but is not in the model (its own error is reported) is skipped.
pub fn check(
    model: &Model,
    declared: &std::collections::HashMap<u32, ()>,
) -> Vec<crate::deck::DeckError> {
    model
        .bulk
        .pload1
        .iter()
        .filter(|c| model.element_index.contains_key(&c.eid) || !declared.contains_key(&c.eid))
        .filter_map(|c| {
            model
                .pload1_loads(c, 1.0)
                .err()
                .map(|e| crate::deck::DeckError::at(&c.loc, e).on_card(format!("PLOAD1 {}", c.sid)))
        })
        .collect()
}

/// X1, X2 of a PLOAD1 as fractions of `length` (they are already when the scale is fractional);
/// X2 beyond the end is an error naming `what` the length is. A position given as a length
/// may reach the end within round-off of the length.
fn fractions_along(card: &Pload1, length: f64, what: &str) -> Result<[f64; 2], String> {
    let at = if card.scale.fractional() {
        card.x
    } else {
        card.x.map(|x| x / length)
    };
    if at[1] > 1.0 + 1e-9 {
        return Err(format!("X2 = {} is beyond {what} {length:e}", card.x[1]));
    }
    Ok(at)
}
