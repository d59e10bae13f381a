//! Equations of an `RSSCON` link ([`RssconLink`]): shell grid S on the solid edge from A
//! (bottom) to B (top), h = |x_B − x_A|, n = (x_B − x_A)/h (the shell's thickness direction),
//! ξ the position of S on the edge ([`on_line`]). In basic,
//!
//! ```text
//! u_S = (1 − ξ) u_A + ξ u_B                      (3 translations, S dependent)
//! θ_S − (θ_S·n) n = n × (u_B − u_A) / h          (the 2 rotations normal to n)
//! ```
//!
//! The shell's translations follow the solid edge; its two bending rotations are the edge's
//! rotation, read from the relative motion of its ends (a rigid rotation θ gives
//! u_B − u_A = h θ × n, and n × (θ × n) is θ's part normal to n). Nothing constrains the
//! stretch (u_B − u_A)·n of the edge, so the solid keeps its Poisson thickness change, and
//! nothing constrains the shell's drilling rotation θ_S·n. This is the constraint MSC's QRG
//! describes for RSSCON (shell DOFs dependent; translations tied to the bottom and top solid
//! grids, the two rotations to the edge's relative translations; Poisson effects allowed).
//!
//! In the grids' frames: u_S's three global components are rows of Λ_Sᵀ; the two dependent
//! rotations are the global components c₁, c₂ of S least aligned with n (the third, c₃, stays
//! independent and enters the right-hand side), solved from the two projections
//! p = e_c₁ − (e_c₁·n) n and q = e_c₂ − (e_c₂·n) n of the equation (a 2 × 2 system, regular as
//! e_c₃·n ≠ 0). A shell grid that is a solid grid itself (S = A or B, a shared node) keeps its
//! translations independent (the equation is an identity); only its rotations are tied.

use super::constraints::Relation;
use super::dofs::DofMap;
use super::frames::GridFrames;
use crate::geometry::vec3::{cross, dot, norm, scale, sub};
use crate::model::rsscon::{RssconLink, on_line};

/// Λ of a grid (identity in basic): basic = Λ · global.
fn frame(frames: &GridFrames, grid: usize) -> [[f64; 3]; 3] {
    match frames.rotation(grid) {
        Some(r) => *r,
        None => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    }
}

/// Terms Σ_j (v · Λ_g e_j) u_{g,j} of a basic vector v dotted with grid g's translation, times
/// `factor`.
fn translation_terms(
    frames: &GridFrames,
    grid: usize,
    v: [f64; 3],
    factor: f64,
) -> impl Iterator<Item = (usize, f64)> {
    let l = frame(frames, grid);
    (0..3).filter_map(move |j| {
        let c = factor * (0..3).map(|k| v[k] * l[k][j]).sum::<f64>();
        (c != 0.0).then_some((DofMap::dof(grid, j), c))
    })
}

/// The relations of one link; `owner` names the card in errors (e.g. "RSSCON 7 at deck.dat:12").
pub fn link_relations(
    xyz: &[[f64; 3]],
    frames: &GridFrames,
    owner: &str,
    link: RssconLink,
) -> Vec<Relation> {
    let RssconLink { shell, bottom, top } = link;
    let (a, b) = (xyz[bottom], xyz[top]);
    let Some((xi, _)) = on_line(xyz[shell], a, b) else {
        return Vec::new();
    };
    let h = norm(sub(b, a));
    let n = scale(sub(b, a), 1.0 / h);
    let ls = frame(frames, shell);
    let axis = |c: usize| [ls[0][c], ls[1][c], ls[2][c]];
    let mut out = Vec::new();
    if shell != bottom && shell != top {
        for c in 0..3 {
            let e = axis(c);
            let terms = translation_terms(frames, bottom, e, 1.0 - xi)
                .chain(translation_terms(frames, top, e, xi))
                .collect();
            out.push(Relation {
                dependent: DofMap::dof(shell, c),
                terms,
                owner: owner.to_string(),
            });
        }
    }
    // rotations: c3 is the global axis of S most aligned with n
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| dot(axis(i), n).abs().total_cmp(&dot(axis(j), n).abs()));
    let [c1, c2, c3] = order;
    let project = |c: usize| sub(axis(c), scale(n, dot(axis(c), n)));
    let (p, q) = (project(c1), project(c2));
    // [p·e1 p·e2; q·e1 q·e2] [θ1; θ2] = [p·w − (p·e3) θ3; q·w − (q·e3) θ3], p·w = (p × n)·d / h
    let m = [
        [dot(p, axis(c1)), dot(p, axis(c2))],
        [dot(q, axis(c1)), dot(q, axis(c2))],
    ];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let inv = [
        [m[1][1] / det, -m[0][1] / det],
        [-m[1][0] / det, m[0][0] / det],
    ];
    let rows = [
        (scale(cross(p, n), 1.0 / h), dot(p, axis(c3))),
        (scale(cross(q, n), 1.0 / h), dot(q, axis(c3))),
    ];
    for (k, c) in [c1, c2].into_iter().enumerate() {
        // θ_c = Σ_r inv[k][r] · (v_r · d − s_r θ_c3), d = u_B − u_A (basic)
        let v: [f64; 3] = std::array::from_fn(|i| (0..2).map(|r| inv[k][r] * rows[r].0[i]).sum());
        let s: f64 = (0..2).map(|r| inv[k][r] * rows[r].1).sum();
        let mut terms: Vec<(usize, f64)> = translation_terms(frames, top, v, 1.0)
            .chain(translation_terms(frames, bottom, v, -1.0))
            .collect();
        if s != 0.0 {
            terms.push((DofMap::dof(shell, 3 + c3), -s));
        }
        out.push(Relation {
            dependent: DofMap::dof(shell, 3 + c),
            terms,
            owner: owner.to_string(),
        });
    }
    out
}
