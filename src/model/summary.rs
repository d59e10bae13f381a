//! [`CheckSummary`] (what `paraflex check` prints as JSON) and [`MeshArrays`] for output.

use std::collections::BTreeMap;

use super::mesh::{ElementBlock, MeshArrays};
use super::{ElementKind, Model};
use crate::fe::shell_quadratic::Quadratic;

/// Counts and mass properties of a model, serialized as
/// `{"grids", "elements": {card: n}, "rigid": {"RBE2", "RBE3"}, "dofs", "mass", "cg",
/// "inertia_cg", "warnings", "sol", "subcases", "materials", "properties", "coords", "wtmass"}`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CheckSummary {
    pub grids: usize,
    /// Every element card by name (CELAS1, CELAS2 and CONM2 included; a 10-node CTETRA counts
    /// as CTETRA).
    pub elements: BTreeMap<&'static str, usize>,
    /// RBE2 and RBE3 counts (both keys always present).
    pub rigid: BTreeMap<&'static str, usize>,
    /// 6 × grids.
    pub dofs: usize,
    pub mass: f64,
    pub cg: [f64; 3],
    pub inertia_cg: [[f64; 3]; 3],
    /// Every warning, rendered.
    pub warnings: Vec<String>,
    /// The solution sequence (`MODAL`, …) or null.
    pub sol: Option<&'static str>,
    /// Subcase ids.
    pub subcases: Vec<u32>,
    /// Material cards by name.
    pub materials: BTreeMap<&'static str, usize>,
    /// Property cards by name.
    pub properties: BTreeMap<&'static str, usize>,
    /// Number of coordinate systems (basic excluded).
    pub coords: usize,
    /// PARAM,WTMASS applied to mass and inertia.
    pub wtmass: f64,
}

impl Model {
    /// The check summary.
    pub fn summary(&self) -> CheckSummary {
        let mut elements = BTreeMap::new();
        for e in &self.elements {
            *elements.entry(e.kind.card()).or_insert(0) += 1;
        }
        let mut rigid = BTreeMap::from([("RBE2", 0), ("RBE3", 0)]);
        for r in &self.rigids {
            *rigid.entry(r.kind.card()).or_insert(0) += 1;
        }
        let b = &self.bulk;
        let nonzero = |pairs: &[(&'static str, usize)]| {
            pairs
                .iter()
                .copied()
                .filter(|(_, n)| *n > 0)
                .collect::<BTreeMap<_, _>>()
        };
        let mp = self.mass_properties();
        CheckSummary {
            grids: self.grids.len(),
            elements,
            rigid,
            dofs: 6 * self.grids.len() + self.scalar_points.len(),
            mass: mp.mass,
            cg: mp.cg,
            inertia_cg: mp.inertia_cg,
            warnings: self.warnings.iter().map(|w| w.to_string()).collect(),
            sol: self.sol.map(|s| s.name()),
            subcases: self.subcases.iter().map(|s| s.id).collect(),
            materials: nonzero(&[
                ("MAT1", b.mat1.len()),
                ("MAT8", b.mat8.len()),
                ("MAT2", b.mat2.len()),
            ]),
            properties: nonzero(&[
                ("PSHELL", b.pshell.len()),
                ("PCOMP", b.pcomp.len()),
                ("PSOLID", b.psolid.len()),
                ("PELAS", b.pelas.len()),
                ("PROD", b.prod.len()),
                ("PTUBE", b.ptube.len()),
                ("PBAR", b.pbar.len()),
                ("PBARL", b.pbarl.len()),
                ("PBEAM", b.pbeam.len()),
                ("PBEAML", b.pbeaml.len()),
            ]),
            coords: self.coords.len().saturating_sub(1),
            wtmass: mp.wtmass,
        }
    }

    /// Grids and connectivity as flat arrays (see [`MeshArrays`]). Blocks are in the order
    /// CQUAD4, CTRIA3, CQUADR, CTRIAR, CQUAD8, CQUAD8_CORNERS, CTRIA6, CTRIA6_CORNERS, CSHEAR, CHEXA,
    /// CPENTA, CTETRA, CTETRA10, CTETRA10_CORNERS, CHEXA20 and CPENTA15 (their corner grids only), CELAS1–CELAS4,
    /// CDAMP1–CDAMP4, CVISC, CBUSH, CONM2, CROD, CONROD, CTUBE, CBAR, CBEAM, RBE2, RBE3.
    pub fn mesh_arrays(&self) -> MeshArrays {
        let mut blocks: BTreeMap<(ElementKind, bool), ElementBlock> = BTreeMap::new();
        for e in &self.elements {
            if e.nodes.is_empty() {
                // a scalar element between scalar points and ground has no place in the mesh
                continue;
            }
            // a CQUAD8 / CTRIA6 / CTETRA 10 with a blank mid-side grid is drawn by its corners
            let tetra_blank = e.kind == ElementKind::Tetra10 && e.nodes.len() < 10;
            let corners = (self.quadratic_layout(e))
                .filter(|l| l.has_blank())
                .map(|l| match l.shape {
                    Quadratic::Quad8 => (4, "CQUAD8_CORNERS"),
                    Quadratic::Tria6 => (3, "CTRIA6_CORNERS"),
                })
                .or(tetra_blank.then_some((4, "CTETRA10_CORNERS")));
            let (nodes, card) = match corners {
                Some((n, card)) => (&e.nodes[..n], card),
                None => (&e.nodes[..], e.kind.block_name()),
            };
            let per = match e.kind {
                k if k.is_scalar_spring() || k.is_damper() || k == ElementKind::Cbush => 2,
                // quadratic CHEXA / CPENTA (mid-side grids may be blank) as their corner cells
                ElementKind::Hexa20 => 8,
                ElementKind::Penta15 => 6,
                _ => nodes.len(),
            };
            let block = blocks
                .entry((e.kind, corners.is_some()))
                .or_insert_with(|| ElementBlock {
                    card,
                    ids: Vec::new(),
                    pids: Vec::new(),
                    nodes_per_element: per,
                    connectivity: Vec::new(),
                });
            block.ids.push(e.id);
            block.pids.push(self.pid_of(e));
            let mut conn: Vec<u32> = nodes.iter().take(per).map(|&n| n as u32).collect();
            while conn.len() < per {
                // a grounded spring end repeats the spring's grid
                conn.push(conn.first().copied().unwrap_or(0));
            }
            block.connectivity.extend(conn);
        }
        let mut out: Vec<ElementBlock> = blocks.into_values().collect();
        for card in ["RBE2", "RBE3", "RSSCON"] {
            let mut block = ElementBlock {
                card,
                ids: Vec::new(),
                pids: Vec::new(),
                nodes_per_element: 2,
                connectivity: Vec::new(),
            };
            for r in self.rigids.iter().filter(|r| r.kind.card() == card) {
                for &leg in &r.legs {
                    block.ids.push(r.id);
                    block.pids.push(0);
                    block.connectivity.extend([r.hub as u32, leg as u32]);
                }
            }
            if !block.ids.is_empty() {
                out.push(block);
            }
        }
        MeshArrays {
            grid_ids: self.grids.iter().map(|g| g.id).collect(),
            xyz: self.grids.iter().map(|g| g.xyz).collect(),
            blocks: out,
        }
    }

    fn pid_of(&self, e: &super::Element) -> u32 {
        let b = &self.bulk;
        match e.kind {
            ElementKind::Quad4 => b.cquad4.get(e.card).map(|c| c.pid),
            ElementKind::Tria3 => b.ctria3.get(e.card).map(|c| c.pid),
            ElementKind::QuadR => b.cquadr.get(e.card).map(|c| c.pid),
            ElementKind::TriaR => b.ctriar.get(e.card).map(|c| c.pid),
            ElementKind::Quad8 => b.cquad8.get(e.card).map(|c| c.pid),
            ElementKind::Tria6 => b.ctria6.get(e.card).map(|c| c.pid),
            ElementKind::Cshear => b.cshear.get(e.card).map(|c| c.pid),
            ElementKind::Hexa8 | ElementKind::Hexa20 => b.chexa.get(e.card).map(|c| c.pid),
            ElementKind::Penta6 | ElementKind::Penta15 => b.cpenta.get(e.card).map(|c| c.pid),
            ElementKind::Pyram5 => b.cpyram.get(e.card).map(|c| c.pid),
            ElementKind::Tetra4 | ElementKind::Tetra10 => b.ctetra.get(e.card).map(|c| c.pid),
            ElementKind::Celas1 => b.celas1.get(e.card).map(|c| c.pid),
            ElementKind::Celas3 => b.celas3.get(e.card).map(|c| c.pid),
            ElementKind::Cdamp1 => b.cdamp1.get(e.card).map(|c| c.pid),
            ElementKind::Cdamp3 => b.cdamp3.get(e.card).map(|c| c.pid),
            ElementKind::Cvisc => b.cvisc.get(e.card).map(|c| c.pid),
            ElementKind::Cbush => b.cbush.get(e.card).map(|c| c.pid),
            ElementKind::Crod => b.crod.get(e.card).map(|c| c.pid),
            ElementKind::Ctube => b.ctube.get(e.card).map(|c| c.pid),
            ElementKind::Cbar => b.cbar.get(e.card).map(|c| c.pid),
            ElementKind::Cbeam => b.cbeam.get(e.card).map(|c| c.pid),
            ElementKind::Cbend => b.cbend.get(e.card).map(|c| c.pid),
            ElementKind::Conrod => None,
            ElementKind::Celas2
            | ElementKind::Celas4
            | ElementKind::Cdamp2
            | ElementKind::Cdamp4
            | ElementKind::Cmass2
            | ElementKind::Conm2 => None,
        }
        .unwrap_or(0)
    }
}
