//! Coordinate systems: `CORD2R` / `CORD2C` / `CORD2S` resolved to the basic system.
//!
//! A `CORD2x` gives three points A (origin), B (on the local z axis) and C (in the local x–z
//! plane) in its reference system RID. The axes follow the Nastran construction:
//!
//! ```text
//! k = (B − A) / |B − A|,   j = k × (C − A) / |k × (C − A)|,   i = j × k
//! ```
//!
//! Systems are resolved in dependency order (RID first). A missing RID, an RID cycle or a
//! degenerate definition (A = B, or C on the A–B line) is an error on the offending card; a
//! system whose RID is itself in error is skipped silently (the root cause is reported once).
//!
//! Point coordinates in a system: rectangular (x, y, z); cylindrical (r, θ in degrees, z);
//! spherical (r, θ from the local z axis, φ about z from the local x axis, both in degrees).

use std::collections::HashMap;

use crate::deck::DeckError;
use crate::deck::cards::{Cord2, CordKind};

use crate::geometry::vec3::{add, cross, dot, norm, scale, sub};

/// Relative tolerance for degenerate definitions: |B − A| and |k × (C − A)| must exceed this
/// fraction of the size of the definition (largest |A|, |B|, |C|, at least 1e-300).
pub const DEGENERATE_TOL: f64 = 1e-10;

/// A resolved coordinate system: origin and unit axes in the basic system.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordSystem {
    pub id: u32,
    pub kind: CordKind,
    /// Origin in basic.
    pub origin: [f64; 3],
    /// Rows: the local x, y, z unit vectors in basic.
    pub axes: [[f64; 3]; 3],
}

impl CoordSystem {
    /// The basic system (id 0).
    pub fn basic() -> Self {
        CoordSystem {
            id: 0,
            kind: CordKind::Rectangular,
            origin: [0.0; 3],
            axes: [[1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
        }
    }

    /// Point coordinates of this system (r, θ°, z for cylindrical; r, θ°, φ° for spherical) →
    /// basic.
    pub fn point_to_basic(&self, p: [f64; 3]) -> [f64; 3] {
        add(self.origin, self.vector_to_basic(self.to_cartesian(p)))
    }

    /// Components along the local Cartesian axes (i, j, k) → basic components.
    pub fn vector_to_basic(&self, v: [f64; 3]) -> [f64; 3] {
        let [i, j, k] = self.axes;
        add(add(scale(i, v[0]), scale(j, v[1])), scale(k, v[2]))
    }

    /// Local coordinates (r, θ°, z for cylindrical; r, θ°, φ° for spherical) → local Cartesian
    /// (x, y, z).
    pub fn to_cartesian(&self, p: [f64; 3]) -> [f64; 3] {
        match self.kind {
            CordKind::Rectangular => p,
            CordKind::Cylindrical => {
                let t = p[1].to_radians();
                [p[0] * t.cos(), p[0] * t.sin(), p[2]]
            }
            CordKind::Spherical => {
                let (st, ct) = p[1].to_radians().sin_cos();
                let (sf, cf) = p[2].to_radians().sin_cos();
                [p[0] * st * cf, p[0] * st * sf, p[0] * ct]
            }
        }
    }

    /// Basic point → local Cartesian (x, y, z) relative to the origin.
    pub fn basic_to_local_cartesian(&self, p: [f64; 3]) -> [f64; 3] {
        let d = sub(p, self.origin);
        let [i, j, k] = self.axes;
        [dot(d, i), dot(d, j), dot(d, k)]
    }

    /// Whether basic point `p` lies on the polar axis (the local z axis) of a cylindrical or
    /// spherical system, where the local directions are undefined (e_r, e_θ of a cylinder; e_θ,
    /// e_φ of a sphere, and all three at its origin): the distance from the axis at or below the
    /// round-off of p − origin, 64 ε (|p| + |origin|). Always false for a rectangular system.
    pub fn on_polar_axis(&self, p: [f64; 3]) -> bool {
        let l = self.basic_to_local_cartesian(p);
        self.kind != CordKind::Rectangular
            && l[0].hypot(l[1]) <= 64.0 * f64::EPSILON * (norm(p) + norm(self.origin))
    }

    /// The 3×3 matrix T whose columns are the local Cartesian axes *at basic point `p`* in
    /// basic: (i, j, k) for rectangular, (e_r, e_θ, e_z) for cylindrical, (e_r, e_θ, e_φ) for
    /// spherical. A vector with local components v has basic components T·v. On the polar axis
    /// ([`Self::on_polar_axis`]) the azimuth is 0 (cylindrical e_r = i, e_θ = j; spherical
    /// e_r = ±k, e_θ = ±i, e_φ = j, with θ = 0 at the origin), not the angle of the last bits of
    /// p; a GRID there that uses the system as its CD gets these directions, with a warning.
    pub fn axes_at(&self, p: [f64; 3]) -> [[f64; 3]; 3] {
        let [i, j, k] = self.axes;
        let l = self.basic_to_local_cartesian(p);
        let azimuth = if self.on_polar_axis(p) {
            0.0
        } else {
            l[1].atan2(l[0])
        };
        let (s, c) = azimuth.sin_cos();
        let radial = add(scale(i, c), scale(j, s));
        let tangential = add(scale(i, -s), scale(j, c));
        let columns = match self.kind {
            CordKind::Rectangular => [i, j, k],
            CordKind::Cylindrical => [radial, tangential, k],
            CordKind::Spherical => {
                // polar angle from +z; 0 at the origin and on the +z half-axis, π on −z
                let (st, ct) = l[0].hypot(l[1]).atan2(l[2]).sin_cos();
                [
                    add(scale(radial, st), scale(k, ct)),
                    add(scale(radial, ct), scale(k, -st)),
                    tangential,
                ]
            }
        };
        std::array::from_fn(|row| std::array::from_fn(|col| columns[col][row]))
    }
}

/// Resolve every `CORD2x` card. Returns the systems by id (basic included) and the errors.
pub fn resolve(cards: &[Cord2], errors: &mut Vec<DeckError>) -> HashMap<u32, CoordSystem> {
    let mut by_id: HashMap<u32, &Cord2> = HashMap::new();
    for c in cards {
        by_id.entry(c.id).or_insert(c);
    }
    let mut done: HashMap<u32, CoordSystem> = HashMap::new();
    done.insert(0, CoordSystem::basic());
    let mut failed: Vec<u32> = Vec::new();
    for c in cards {
        if done.contains_key(&c.id) || failed.contains(&c.id) {
            continue;
        }
        // walk the RID chain from c until a resolved system, a missing one or a cycle
        let mut chain: Vec<&Cord2> = vec![c];
        let outcome = loop {
            let last = chain[chain.len() - 1];
            if done.contains_key(&last.rid) {
                break Ok(());
            }
            if failed.contains(&last.rid) {
                break Err(None);
            }
            match by_id.get(&last.rid) {
                None => {
                    break Err(Some(err(
                        last,
                        format!(
                            "RID = {} does not exist (no CORD2R/CORD2C/CORD2S with this id)",
                            last.rid
                        ),
                    )));
                }
                Some(next) => {
                    if chain.iter().any(|x| x.id == next.id) {
                        let ids: Vec<String> = chain.iter().map(|x| x.id.to_string()).collect();
                        break Err(Some(err(
                            last,
                            format!("RID cycle: systems {} refer to each other", ids.join(" → ")),
                        )));
                    }
                    chain.push(next);
                }
            }
        };
        match outcome {
            Ok(()) => {
                for card in chain.iter().rev() {
                    let Some(reference) = done.get(&card.rid) else {
                        break;
                    };
                    match build(card, reference) {
                        Ok(sys) => {
                            done.insert(card.id, sys);
                        }
                        Err(e) => {
                            errors.push(e);
                            failed.extend(chain.iter().map(|x| x.id));
                            break;
                        }
                    }
                }
            }
            Err(e) => {
                errors.extend(e);
                failed.extend(chain.iter().map(|x| x.id));
            }
        }
    }
    done
}

fn err(card: &Cord2, message: String) -> DeckError {
    DeckError::at(&card.loc, message).on_card(format!("{} {}", kind_name(card.kind), card.id))
}

/// Card name of a system kind.
pub fn kind_name(kind: CordKind) -> &'static str {
    match kind {
        CordKind::Rectangular => "CORD2R",
        CordKind::Cylindrical => "CORD2C",
        CordKind::Spherical => "CORD2S",
    }
}

/// Build one system from its card, with A, B, C given in `reference`.
fn build(card: &Cord2, reference: &CoordSystem) -> Result<CoordSystem, DeckError> {
    if ![card.a, card.b, card.c]
        .iter()
        .flatten()
        .all(|v| v.is_finite())
    {
        return Err(err(card, "A, B, C must be finite".into()));
    }
    let a = reference.point_to_basic(card.a);
    let b = reference.point_to_basic(card.b);
    let c = reference.point_to_basic(card.c);
    let size = [norm(a), norm(b), norm(c), norm(sub(b, a)), norm(sub(c, a))]
        .into_iter()
        .fold(1e-300, f64::max);
    let ab = sub(b, a);
    if norm(ab) <= DEGENERATE_TOL * size {
        return Err(err(
            card,
            "degenerate system: A and B coincide, so the z axis is undefined".into(),
        ));
    }
    let k = scale(ab, 1.0 / norm(ab));
    let jv = cross(k, sub(c, a));
    if norm(jv) <= DEGENERATE_TOL * size {
        return Err(err(
            card,
            "degenerate system: C lies on the z axis (the A–B line), so the x–z plane is undefined"
                .into(),
        ));
    }
    let j = scale(jv, 1.0 / norm(jv));
    let i = cross(j, k);
    Ok(CoordSystem {
        id: card.id,
        kind: card.kind,
        origin: a,
        axes: [i, j, k],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::Loc;
    use std::path::Path;
    use std::sync::Arc;

    fn card(id: u32, kind: CordKind, rid: u32, a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Cord2 {
        let file: Arc<Path> = Arc::from(Path::new("t.bdf"));
        Cord2 {
            id,
            kind,
            rid,
            a,
            b,
            c,
            loc: Loc::new(&file, id),
        }
    }

    #[test]
    fn nested_cylindrical_point() {
        // rectangular system shifted by (1,0,0) and rotated 90° about z; cylindrical inside it
        let r = card(
            1,
            CordKind::Rectangular,
            0,
            [1., 0., 0.],
            [1., 0., 1.],
            [1., 1., 0.],
        );
        let cyl = card(
            2,
            CordKind::Cylindrical,
            1,
            [0., 0., 0.],
            [0., 0., 1.],
            [1., 0., 0.],
        );
        let mut errors = Vec::new();
        let sys = resolve(&[cyl, r], &mut errors);
        assert!(errors.is_empty());
        // r = 2, θ = 90° in system 2 → local (0, 2, 0) of system 1 → basic (1 − 2, 0, 0)
        let p = sys[&2].point_to_basic([2.0, 90.0, 0.5]);
        assert!(
            (p[0] + 1.0).abs() < 1e-14 && p[1].abs() < 1e-14 && (p[2] - 0.5).abs() < 1e-14,
            "{p:?}"
        );
    }

    /// A grid on the polar axis gets θ = 0 (the system's own i, j) whether its coordinates put
    /// it there exactly or up to round-off; just off the axis, e_r follows the point.
    #[test]
    fn polar_axis_takes_theta_zero() {
        let cyl = card(
            3,
            CordKind::Cylindrical,
            0,
            [0., 1., 0.],
            [0., 1., 1.],
            [1., 1., 0.],
        );
        let mut errors = Vec::new();
        let sys = resolve(&[cyl], &mut errors);
        assert!(errors.is_empty());
        assert!(
            sys[&3].on_polar_axis([1e-17, 1.0 - 1e-16, 5.0])
                && !sys[&3].on_polar_axis([0.0, 1.0 - 1e-9, 5.0])
        );
        let exact = sys[&3].axes_at([0.0, 1.0, 5.0]);
        let rounded = sys[&3].axes_at([1e-17, 1.0 - 1e-16, 5.0]);
        assert_eq!(exact, [[1., 0., 0.], [0., 1., 0.], [0., 0., 1.]]);
        assert_eq!(rounded, exact);
        // 1e-9 off the axis along −y: e_r = −y
        let off = sys[&3].axes_at([0.0, 1.0 - 1e-9, 5.0]);
        assert!(off[1][0] + 1.0 < 1e-12 && off[0][0].abs() < 1e-6, "{off:?}");
    }

    /// A spherical system tilted in basic: a point given as (r, θ, φ) lands at r from the origin,
    /// θ from the system's z axis and φ from its x–z plane; the local axes there are e_r along
    /// the radius, e_φ = k × e_r / |k × e_r| and e_θ = e_φ × e_r (right-handed), each checked
    /// without the formulas of `to_cartesian`/`axes_at`; on the polar axis e_φ = j.
    #[test]
    fn spherical_point_and_axes() {
        let sph = card(
            4,
            CordKind::Spherical,
            0,
            [1., 2., 3.],
            [1.3, 2.4, 4.],
            [2., 2., 3.],
        );
        let mut errors = Vec::new();
        let sys = resolve(&[sph], &mut errors);
        assert!(errors.is_empty());
        let s = &sys[&4];
        let [i, j, k] = s.axes;
        for (r, theta, phi) in [(2.0, 30.0, 40.0), (0.5, 120.0, -75.0), (3.0, 90.0, 180.0)] {
            let p = s.point_to_basic([r, theta, phi]);
            let d = sub(p, s.origin);
            let (rho, t, f) = (norm(d), theta.to_radians(), phi.to_radians());
            assert!((rho - r).abs() < 1e-14 * r, "{rho} vs {r}");
            assert!((dot(d, k) / rho - t.cos()).abs() < 1e-14);
            assert!(
                (dot(d, j).atan2(dot(d, i)) - f).abs() < 1e-13 || f.abs() == std::f64::consts::PI
            );
            let t_at = s.axes_at(p);
            let col = |c: usize| [t_at[0][c], t_at[1][c], t_at[2][c]];
            let e_r = scale(d, 1.0 / rho);
            let kr = cross(k, e_r);
            let e_phi = scale(kr, 1.0 / norm(kr));
            let e_theta = cross(e_phi, e_r);
            for (c, e) in [(0, e_r), (1, e_theta), (2, e_phi)] {
                assert!(
                    norm(sub(col(c), e)) < 1e-14,
                    "r {r} θ {theta} φ {phi} axis {c}"
                );
            }
        }
        // polar axis: φ = 0, e_r = ±k, e_φ = j
        let top = s.point_to_basic([2.0, 0.0, 0.0]);
        assert!(s.on_polar_axis(top));
        let t_at = s.axes_at(top);
        assert!(
            (0..3).all(|row| (t_at[row][0] - k[row]).abs() < 1e-15
                && (t_at[row][2] - j[row]).abs() < 1e-15)
        );
    }

    #[test]
    fn cycle_missing_and_degenerate_are_errors() {
        let a = card(
            1,
            CordKind::Rectangular,
            2,
            [0.; 3],
            [0., 0., 1.],
            [1., 0., 0.],
        );
        let b = card(
            2,
            CordKind::Rectangular,
            1,
            [0.; 3],
            [0., 0., 1.],
            [1., 0., 0.],
        );
        let c = card(
            3,
            CordKind::Rectangular,
            9,
            [0.; 3],
            [0., 0., 1.],
            [1., 0., 0.],
        );
        let d = card(4, CordKind::Rectangular, 0, [0.; 3], [0.; 3], [1., 0., 0.]);
        let e = card(
            5,
            CordKind::Cylindrical,
            0,
            [0.; 3],
            [0., 0., 1.],
            [0., 0., 3.],
        );
        let mut errors = Vec::new();
        let sys = resolve(&[a, b, c, d, e], &mut errors);
        assert_eq!(sys.len(), 1);
        let text: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
        assert_eq!(errors.len(), 4, "{text:#?}");
        assert!(text.iter().any(|t| t.contains("RID cycle")));
        assert!(
            text.iter()
                .any(|t| t.contains("CORD2R 3: RID = 9 does not exist"))
        );
        assert!(text.iter().any(|t| t.contains("A and B coincide")));
        assert!(
            text.iter()
                .any(|t| t.contains("CORD2C 5") && t.contains("C lies on the z axis"))
        );
    }
}
