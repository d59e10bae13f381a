//! Pressure cards (`PLOAD4`, `PLOAD2`, `PLOAD`) resolved to loaded faces: the face's grids in
//! the order whose right-hand normal is the direction of positive pressure, its corner
//! pressures in that order, and the direction of the load; [`crate::fe::pressure`] turns a
//! face into consistent nodal forces.
//!
//! Shell faces keep the element's grid order (positive pressure along the G1 → G2 → G3
//! normal). A solid face is found from G1 and G3 (CHEXA, CPENTA quadrilateral faces: diagonal
//! corners), G1 alone (CPENTA triangular faces) or G4 (CTETRA: the corner off the face), ordered
//! from G1 so that its normal points into the element (positive pressure pushes inward, as in
//! Nastran), mid-side grids of a 10-node CTETRA after the corners.

use super::{ElementKind, Model};
use crate::deck::cards::{Pload, Pload2, Pload4, Pload4Target};
use crate::fe::pressure::{Direction, face_forces};
use crate::fe::shell_quadratic::Layout;
use crate::geometry::vec3::{cross, dot, norm, scale, sub};

/// A loaded face: grid indices into [`Model::grids`], corner pressures, direction.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedFace {
    pub grids: Vec<usize>,
    pub pressures: Vec<f64>,
    pub direction: Direction,
    /// The face of a CQUAD8 / CTRIA6: which of its mid-side grids are given (`grids` holds
    /// the given ones); a blank one is tied to its edge's corners, as in the element.
    pub layout: Option<Layout>,
}

impl LoadedFace {
    /// Consistent nodal forces (basic) on `grids`, from their positions `xyz`.
    pub fn forces(&self, xyz: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let Some(layout) = self.layout.filter(|l| l.has_blank()) else {
            return face_forces(xyz, &self.pressures, self.direction);
        };
        match layout.complete(xyz) {
            Ok(full) => {
                let f = face_forces(&full, &self.pressures, self.direction);
                let flat: Vec<f64> = f.iter().flatten().copied().collect();
                layout
                    .condense(&flat, 3)
                    .chunks(3)
                    .map(|c| [c[0], c[1], c[2]])
                    .collect()
            }
            // the grid list does not match the layout: no load (the element itself is refused)
            Err(_) => vec![[0.0; 3]; xyz.len()],
        }
    }
}

impl Model {
    /// The faces a `PLOAD4` loads, or what is wrong with it (element missing or without faces,
    /// G1/G3/G4 not on it, a curvilinear or missing CID).
    pub fn pload4_faces(&self, card: &Pload4) -> Result<Vec<LoadedFace>, String> {
        let direction = match card.direction {
            None => Direction::Normal,
            Some((cid, n)) => match self.coords.get(&cid) {
                Some(c) if c.kind == crate::deck::cards::CordKind::Rectangular => {
                    let d = c.vector_to_basic(n);
                    Direction::Fixed(scale(d, 1.0 / norm(d)))
                }
                Some(_) => {
                    return Err(format!(
                        "CID = {cid} is curvilinear: give the load direction N in a rectangular system"
                    ));
                }
                None => return Err(format!("CID = {cid} does not exist")),
            },
        };
        match card.target {
            Pload4Target::Range { first, last } => Ok(self
                .elements
                .iter()
                .filter(|e| (first..=last).contains(&e.id))
                .filter(|e| e.kind.is_shell())
                .map(|e| self.shell_face(e, &card.pressures, direction))
                .collect()),
            Pload4Target::Element { eid, g1, g34 } => {
                let element = self
                    .element_index
                    .get(&eid)
                    .map(|&i| &self.elements[i])
                    .ok_or(format!(
                        "EID = {eid} is not a CQUAD4, CTRIA3, CQUADR, CTRIAR, CQUAD8, CTRIA6, CHEXA, CPENTA or CTETRA"
                    ))?;
                let face = match element.kind {
                    ElementKind::Quad4
                    | ElementKind::Tria3
                    | ElementKind::QuadR
                    | ElementKind::TriaR
                    | ElementKind::Quad8
                    | ElementKind::Tria6 => {
                        return Ok(vec![self.shell_face(element, &card.pressures, direction)]);
                    }
                    ElementKind::Hexa8
                    | ElementKind::Penta6
                    | ElementKind::Tetra4
                    | ElementKind::Tetra10
                    | ElementKind::Hexa20
                    | ElementKind::Penta15 => {
                        let grid = |id: Option<u32>, name: &str| -> Result<Option<usize>, String> {
                            id.map(|id| {
                                self.grid_index
                                    .get(&id)
                                    .copied()
                                    .filter(|g| element.nodes.contains(g))
                                    .ok_or(format!(
                                        "{name} = {id} is not a grid of {} {eid}",
                                        element.kind.card()
                                    ))
                            })
                            .transpose()
                        };
                        let (g1, g34) = (grid(g1, "G1")?, grid(g34, "G3/G4")?);
                        let g1 = g1.ok_or(format!(
                            "G1 is required to pick a face of {} {eid}",
                            element.kind.card()
                        ))?;
                        solid_face(self, element, g1, g34)
                            .map_err(|e| format!("{} {eid}: {e}", element.kind.card()))?
                    }
                    _ => {
                        return Err(format!(
                            "EID = {eid} is a {}, which has no face to load",
                            element.kind.card()
                        ));
                    }
                };
                let corners = if face.len() % 4 == 0 { 4 } else { 3 };
                Ok(vec![LoadedFace {
                    grids: face,
                    pressures: card.pressures[..corners].to_vec(),
                    direction,
                    layout: None,
                }])
            }
        }
    }

    /// The shell faces a `PLOAD2` loads, or the listed id that is not a shell.
    pub fn pload2_faces(&self, card: &Pload2) -> Result<Vec<LoadedFace>, String> {
        let shells = |e: &&super::Element| e.kind.is_shell();
        let mut faces = Vec::new();
        for &eid in &card.elements {
            let e = self
                .element_index
                .get(&eid)
                .map(|&i| &self.elements[i])
                .filter(shells)
                .ok_or(format!(
                    "EID = {eid} is not a CQUAD4, CTRIA3, CQUADR, CTRIAR, CQUAD8 or CTRIA6"
                ))?;
            faces.push(self.shell_face(e, &[card.pressure; 4], Direction::Normal));
        }
        if let Some((first, last)) = card.range {
            faces.extend(
                self.elements
                    .iter()
                    .filter(|e| (first..=last).contains(&e.id))
                    .filter(shells)
                    .map(|e| self.shell_face(e, &[card.pressure; 4], Direction::Normal)),
            );
        }
        Ok(faces)
    }

    /// The face of a `PLOAD`, or its grid that does not exist.
    pub fn pload_face(&self, card: &Pload) -> Result<LoadedFace, String> {
        let grids = card
            .grids
            .iter()
            .map(|id| {
                self.grid_index
                    .get(id)
                    .copied()
                    .ok_or(format!("grid {id} does not exist"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(LoadedFace {
            pressures: vec![card.pressure; grids.len()],
            grids,
            direction: Direction::Normal,
            layout: None,
        })
    }
}

impl Model {
    /// The face of a shell element: its grids in its order.
    fn shell_face(
        &self,
        e: &super::Element,
        pressures: &[f64; 4],
        direction: Direction,
    ) -> LoadedFace {
        // one pressure per corner: 4 for CQUAD4 / CQUAD8, 3 for CTRIA3 / CTRIA6
        let corners = match e.kind {
            ElementKind::Quad4 | ElementKind::QuadR | ElementKind::Quad8 => 4,
            _ => 3,
        };
        LoadedFace {
            grids: e.nodes.clone(),
            pressures: pressures[..corners].to_vec(),
            direction,
            layout: self.quadratic_layout(e),
        }
    }
}

/// Local corner numbers of the faces of each solid (any orientation; [`solid_face`] orients).
fn faces_of(kind: ElementKind) -> &'static [&'static [usize]] {
    match kind {
        ElementKind::Hexa8 | ElementKind::Hexa20 => &[
            &[0, 1, 2, 3],
            &[4, 5, 6, 7],
            &[0, 1, 5, 4],
            &[1, 2, 6, 5],
            &[2, 3, 7, 6],
            &[3, 0, 4, 7],
        ],
        ElementKind::Penta6 | ElementKind::Penta15 => &[
            &[0, 1, 2],
            &[3, 4, 5],
            &[0, 1, 4, 3],
            &[1, 2, 5, 4],
            &[2, 0, 3, 5],
        ],
        _ => &[&[0, 1, 2], &[0, 1, 3], &[1, 2, 3], &[2, 0, 3]],
    }
}

/// The loaded face of a solid as grid indices, from G1 (and G3 or G4), oriented inward and
/// starting at G1; a quadratic element's face has its mid-side grids after the corners (in
/// edge order 1–2, 2–3, …), or none when they are all blank (the face is then linear).
fn solid_face(
    model: &Model,
    element: &super::Element,
    g1: usize,
    g34: Option<usize>,
) -> Result<Vec<usize>, String> {
    let (kind, nodes) = (element.kind, &element.nodes[..]);
    let midsides = model
        .solid_midsides(element)
        .expect("a solid element has a kernel topology");
    let local = |g: usize| {
        nodes
            .iter()
            .position(|&n| n == g)
            .expect("checked on the element")
    };
    let (a, other) = (local(g1), g34.map(local));
    let is_tetra = matches!(kind, ElementKind::Tetra4 | ElementKind::Tetra10);
    let candidates: Vec<&[usize]> = faces_of(kind)
        .iter()
        .copied()
        .filter(|f| {
            let at = |k: usize| f.iter().position(|&c| c == k);
            match (is_tetra, other) {
                (true, Some(opposite)) => at(a).is_some() && at(opposite).is_none(),
                (true, None) => false,
                (false, Some(diagonal)) => {
                    f.len() == 4
                        && matches!((at(a), at(diagonal)), (Some(i), Some(j)) if (i + 2) % 4 == j)
                }
                (false, None) => f.len() == 3 && at(a).is_some(),
            }
        })
        .collect();
    let [face] = candidates[..] else {
        return Err(match (is_tetra, kind, other) {
            (true, _, None) => "G4, the corner off the loaded face, is required".into(),
            (true, _, Some(_)) => "G4 must be the corner off the face and G1 a corner on it".into(),
            (false, ElementKind::Hexa8 | ElementKind::Hexa20, _) | (false, _, Some(_)) => {
                "G1 and G3 must be diagonally opposite corners of one quadrilateral face".into()
            }
            _ => "G1 must be a corner of a triangular face (leave G3 blank only for those)".into(),
        });
    };
    let start = face
        .iter()
        .position(|&c| c == a)
        .expect("G1 is on the face");
    let mut corners: Vec<usize> = (0..face.len())
        .map(|k| face[(start + k) % face.len()])
        .collect();
    let xyz = |k: usize| model.grids[nodes[k]].xyz;
    let centre = |ks: &mut dyn Iterator<Item = usize>| {
        let (mut s, mut n) = ([0.0; 3], 0.0);
        for k in ks {
            s = std::array::from_fn(|i| s[i] + xyz(k)[i]);
            n += 1.0;
        }
        scale(s, 1.0 / n)
    };
    let corner_count = crate::fe::solid::corners(midsides.kind());
    let inward = sub(
        centre(&mut (0..corner_count)),
        centre(&mut corners.iter().copied()),
    );
    let normal = cross(
        sub(xyz(corners[1]), xyz(corners[0])),
        sub(xyz(corners[corners.len() - 1]), xyz(corners[0])),
    );
    if dot(normal, inward) < 0.0 {
        corners[1..].reverse();
    }
    let mut face_grids: Vec<usize> = corners.iter().map(|&k| nodes[k]).collect();
    let mids: Vec<Option<usize>> = (0..corners.len())
        .map(|k| midsides.edge_midside(corners[k], corners[(k + 1) % corners.len()]))
        .collect();
    match mids.iter().filter(|m| m.is_some()).count() {
        0 => {}
        n if n == mids.len() => face_grids.extend(mids.iter().flatten().map(|&m| nodes[m])),
        _ => {
            return Err(
                "the loaded face has some but not all of its mid-side grids: a pressure on a face with blank mid-side grids is supported only when all of them are blank".into(),
            );
        }
    }
    Ok(face_grids)
}

/// Every pressure card that cannot be resolved, as a deck error at its line. A card on an element
/// whose card exists (`declared`) but that is not in the model (its own error is reported) or on
/// a grid that is not is skipped: no knock-on errors.
pub fn check(
    model: &Model,
    declared: &std::collections::HashMap<u32, ()>,
) -> Vec<crate::deck::DeckError> {
    let b = &model.bulk;
    let error = |loc: &crate::deck::Loc, card: String, e: String| {
        crate::deck::DeckError::at(loc, e).on_card(card)
    };
    let known = |eid: u32| model.element_index.contains_key(&eid) || !declared.contains_key(&eid);
    let pload4 = b
        .pload4
        .iter()
        .filter(|c| !matches!(c.target, Pload4Target::Element { eid, .. } if !known(eid)))
        .filter_map(|c| {
            model
                .pload4_faces(c)
                .err()
                .map(|e| error(&c.loc, format!("PLOAD4 {}", c.sid), e))
        });
    let pload2 = b
        .pload2
        .iter()
        .filter(|c| c.elements.iter().all(|&eid| known(eid)))
        .filter_map(|c| {
            model
                .pload2_faces(c)
                .err()
                .map(|e| error(&c.loc, format!("PLOAD2 {}", c.sid), e))
        });
    let pload = b
        .pload
        .iter()
        .filter(|c| {
            c.grids
                .iter()
                .all(|g| model.grid_index.contains_key(g) || !b.grids.iter().any(|d| d.id == *g))
        })
        .filter_map(|c| {
            model
                .pload_face(c)
                .err()
                .map(|e| error(&c.loc, format!("PLOAD {}", c.sid), e))
        });
    pload4.chain(pload2).chain(pload).collect()
}
