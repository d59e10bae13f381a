//! `SELOC`: the rigid motion that places a part superelement before it is connected, as the
//! coordinate system that stands for the part's moved basic system.

use std::collections::HashMap;

use crate::deck::cards::{BulkData, Cord2, CordKind, Seloc};
use crate::deck::{DeckError, Warning};
use crate::model::coords::{self, CoordSystem};

/// Relative difference of the PA and PB triangles' sides above which a warning says that the
/// part is placed by PA1, the line PA1–PA2 and the plane PA1–PA2–PA3 only. 1e-4: the decks'
/// eight-column coordinates carry five to six significant digits.
const SIDE_MISMATCH: f64 = 1e-4;

/// Basic location of GRID or POINT `id` of `bulk` (its CP resolved, GRDSET's CP for a blank
/// GRID CP).
fn location(bulk: &BulkData, systems: &HashMap<u32, CoordSystem>, id: u32) -> Option<[f64; 3]> {
    let default_cp = bulk.grdset.first().map_or(0, |d| d.cp);
    let (cp, x) = match bulk.grids.iter().find(|g| g.id == id) {
        Some(g) => (g.cp.unwrap_or(default_cp), g.x),
        None => bulk
            .points
            .iter()
            .find(|p| p.id == id)
            .map(|p| (p.cp, p.x))?,
    };
    Some(systems.get(&cp)?.point_to_basic(x))
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    a.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(a);
    (n > 0.0).then(|| a.map(|x| x / n))
}

/// Orthonormal frame (rows e1, e2, e3) of three points: e1 along p1→p2, e3 normal to their
/// plane; `None` when they are collinear.
fn frame(p: [[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let e1 = unit(sub(p[1], p[0]))?;
    let n = cross(e1, sub(p[2], p[0]));
    if norm(n) <= 1e-12 * norm(sub(p[2], p[0])).max(f64::MIN_POSITIVE) {
        return None;
    }
    let e3 = unit(n)?;
    Some([e1, cross(e3, e1), e3])
}

/// The system standing for part `seloc.seid`'s moved basic system, with id `id`: the rotation
/// takes the PA frame onto the PB frame and PA1 onto PB1.
pub fn moved_basic(
    seloc: &Seloc,
    part: &BulkData,
    residual: &BulkData,
    id: u32,
    warnings: &mut Vec<Warning>,
) -> Result<Cord2, DeckError> {
    let mut ignored = Vec::new();
    let part_systems = coords::resolve(&part.coords, &mut ignored);
    let residual_systems = coords::resolve(&residual.coords, &mut ignored);
    let points =
        |bulk: &BulkData, systems: &HashMap<u32, CoordSystem>, ids: [u32; 3], whose: &str| {
            let mut out = [[0.0; 3]; 3];
            for (k, gid) in ids.into_iter().enumerate() {
                out[k] = location(bulk, systems, gid).ok_or_else(|| {
                    DeckError::at(
                        &seloc.loc,
                        format!(
                            "SELOC {}: {gid} is neither a GRID nor a POINT of {whose}",
                            seloc.seid
                        ),
                    )
                    .on_card(format!("SELOC {}", seloc.seid))
                })?;
            }
            Ok::<_, DeckError>(out)
        };
    let pa = points(
        part,
        &part_systems,
        seloc.pa,
        &format!("part superelement {}", seloc.seid),
    )?;
    let pb = points(residual, &residual_systems, seloc.pb, "the main bulk data")?;
    let collinear = |which: &str| {
        DeckError::at(
            &seloc.loc,
            format!(
                "SELOC {}: the points {which} are collinear; they must span a plane",
                seloc.seid
            ),
        )
        .on_card(format!("SELOC {}", seloc.seid))
    };
    let fa = frame(pa).ok_or_else(|| collinear("PA1–PA3"))?;
    let fb = frame(pb).ok_or_else(|| collinear("PB1–PB3"))?;
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let (la, lb) = (norm(sub(pa[j], pa[i])), norm(sub(pb[j], pb[i])));
        if (la - lb).abs() > SIDE_MISMATCH * la.max(lb) {
            warnings.push(Warning {
                loc: Some(seloc.loc.to_string()),
                message: format!(
                    "SELOC {}: PA{}–PA{} is {la:.6e} long and PB{}–PB{} {lb:.6e}: the part is placed by PA1, the line PA1–PA2 and the plane PA1–PA2–PA3",
                    seloc.seid,
                    i + 1,
                    j + 1,
                    i + 1,
                    j + 1
                ),
            });
            break;
        }
    }
    // R = Σ_k fb_k ⊗ fa_k maps the part's basic components to basic ones
    let rotate = |v: [f64; 3]| -> [f64; 3] {
        let mut out = [0.0; 3];
        for k in 0..3 {
            let c: f64 = (0..3).map(|l| fa[k][l] * v[l]).sum();
            (0..3).for_each(|l| out[l] += c * fb[k][l]);
        }
        out
    };
    let r_pa1 = rotate(pa[0]);
    let origin = sub(pb[0], r_pa1);
    let along = |v: [f64; 3]| {
        let r = rotate(v);
        [origin[0] + r[0], origin[1] + r[1], origin[2] + r[2]]
    };
    Ok(Cord2 {
        id,
        kind: CordKind::Rectangular,
        rid: 0,
        a: origin,
        b: along([0.0, 0.0, 1.0]),
        c: along([1.0, 0.0, 0.0]),
        loc: seloc.loc.clone(),
    })
}
