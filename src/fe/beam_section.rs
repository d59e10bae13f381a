//! Cross-section properties of the `PBARL` / `PBEAML` library shapes: area A, bending inertias
//! I1 = ∫y² dA (plane 1, bending about the element z axis), I2 = ∫z² dA, product I12 = ∫yz dA,
//! all about the centroid, and the torsion constant J.
//!
//! Axes follow the Nastran PBARL figures: y (plane 1) is "up" on the figure, z across. Each
//! shape is a union of rectangles whose A, I1, I2, I12 follow exactly from the parallel-axis
//! theorem; J uses the formulas of the Nastran element library for each shape:
//!
//! | TYPE | DIM1 … | J |
//! |---|---|---|
//! | ROD | r | π r⁴ / 2 |
//! | TUBE | r_outer, r_inner | π (r_o⁴ − r_i⁴) / 2 |
//! | BAR | width (z), height (y) | a b³ (1/3 − 0.21 (b/a)(1 − b⁴/(12 a⁴))), a ≥ b the longer and shorter side |
//! | BOX | width, height, t of top/bottom walls, t of side walls | thin-walled closed: 2 t₂ t₁ (w−t₂)² (h−t₁)² / (w t₂ + h t₁ − t₂² − t₁²) |
//! | I | height, bottom flange width, top flange width, web t, bottom flange t, top flange t | open: (w_b t_b³ + w_t t_t³ + (h − (t_b + t_t)/2) t_w³) / 3 |
//! | CHAN | width, height, web t, flange t | open: (2 (w − t_w/2) t_f³ + (h − t_f) t_w³) / 3 |
//! | T | flange width, height, flange t, web t | open: (w t_f³ + (h − t_f/2) t_w³) / 3 |
//! | L | width (z), height (y), t of the horizontal leg, t of the vertical leg | open: ((w − t_v/2) t_h³ + (h − t_h/2) t_v³) / 3 |
//!
//! Every other library shape is refused by name ([`SectionError::UnsupportedType`]).

/// Properties of a cross-section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionProperties {
    pub a: f64,
    pub i1: f64,
    pub i2: f64,
    pub i12: f64,
    pub j: f64,
}

/// Errors of the library shapes.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SectionError {
    #[error(
        "TYPE = {0} is not supported; paraflex computes the shapes {SUPPORTED_LIST} (give the section on a PBAR/PBEAM instead)"
    )]
    UnsupportedType(String),
    #[error("TYPE = {shape} needs {needed} dimensions DIM1…DIM{needed}, found {found}")]
    DimensionCount {
        shape: &'static str,
        needed: usize,
        found: usize,
    },
    #[error("TYPE = {shape}: {rule} (DIM = {dims:?})")]
    Inconsistent {
        shape: &'static str,
        rule: &'static str,
        dims: Vec<f64>,
    },
}

/// The supported shapes with their numbers of dimensions.
pub const SUPPORTED: [(&str, usize); 8] = [
    ("ROD", 1),
    ("TUBE", 2),
    ("BAR", 2),
    ("BOX", 4),
    ("I", 6),
    ("CHAN", 4),
    ("T", 4),
    ("L", 4),
];

const SUPPORTED_LIST: &str = "ROD, TUBE, BAR, BOX, I, CHAN, T, L";

/// The number of dimensions of a supported shape (`None` for other names).
pub fn dimension_count(shape: &str) -> Option<usize> {
    SUPPORTED.iter().find(|(n, _)| *n == shape).map(|(_, n)| *n)
}

/// A rectangle: width along z, height along y, centre (z, y).
#[derive(Clone, Copy)]
struct Rect {
    width: f64,
    height: f64,
    z: f64,
    y: f64,
}

/// A, I1, I2, I12 of a union of rectangles about its centroid (parallel-axis theorem).
fn rectangles(parts: &[Rect]) -> (f64, f64, f64, f64) {
    let a: f64 = parts.iter().map(|r| r.width * r.height).sum();
    let zc = parts.iter().map(|r| r.width * r.height * r.z).sum::<f64>() / a;
    let yc = parts.iter().map(|r| r.width * r.height * r.y).sum::<f64>() / a;
    let (mut i1, mut i2, mut i12) = (0.0, 0.0, 0.0);
    for r in parts {
        let ar = r.width * r.height;
        let (dy, dz) = (r.y - yc, r.z - zc);
        i1 += r.width * r.height.powi(3) / 12.0 + ar * dy * dy;
        i2 += r.height * r.width.powi(3) / 12.0 + ar * dz * dz;
        i12 += ar * dy * dz;
    }
    (a, i1, i2, i12)
}

/// Section properties of a library shape `shape` (upper case) with dimensions `dims`.
pub fn library_section(shape: &str, dims: &[f64]) -> Result<SectionProperties, SectionError> {
    let Some(&(name, needed)) = SUPPORTED.iter().find(|(n, _)| *n == shape) else {
        return Err(SectionError::UnsupportedType(shape.to_string()));
    };
    if dims.len() != needed {
        return Err(SectionError::DimensionCount {
            shape: name,
            needed,
            found: dims.len(),
        });
    }
    let bad = |rule| SectionError::Inconsistent {
        shape: name,
        rule,
        dims: dims.to_vec(),
    };
    if dims.iter().any(|d| !(*d > 0.0) || !d.is_finite()) {
        return Err(bad("every dimension must be > 0"));
    }
    let pi = std::f64::consts::PI;
    let d = dims;
    let rect = |width, height, z, y| Rect {
        width,
        height,
        z,
        y,
    };
    let (parts, j) = match name {
        "ROD" => {
            let i = pi * d[0].powi(4) / 4.0;
            return Ok(SectionProperties {
                a: pi * d[0] * d[0],
                i1: i,
                i2: i,
                i12: 0.0,
                j: 2.0 * i,
            });
        }
        "TUBE" => {
            if d[1] >= d[0] {
                return Err(bad("DIM2 (inner radius) must be < DIM1 (outer radius)"));
            }
            let i = pi * (d[0].powi(4) - d[1].powi(4)) / 4.0;
            return Ok(SectionProperties {
                a: pi * (d[0] * d[0] - d[1] * d[1]),
                i1: i,
                i2: i,
                i12: 0.0,
                j: 2.0 * i,
            });
        }
        "BAR" => {
            let (long, short) = (d[0].max(d[1]), d[0].min(d[1]));
            let ratio = short / long;
            let j =
                long * short.powi(3) * (1.0 / 3.0 - 0.21 * ratio * (1.0 - ratio.powi(4) / 12.0));
            (vec![rect(d[0], d[1], 0.0, 0.0)], j)
        }
        "BOX" => {
            let (w, h, t1, t2) = (d[0], d[1], d[2], d[3]);
            if w <= 2.0 * t2 || h <= 2.0 * t1 {
                return Err(bad("DIM1 > 2·DIM4 and DIM2 > 2·DIM3 are required"));
            }
            let side = h - 2.0 * t1;
            let parts = vec![
                rect(w, t1, 0.0, (h - t1) / 2.0),
                rect(w, t1, 0.0, -(h - t1) / 2.0),
                rect(t2, side, (w - t2) / 2.0, 0.0),
                rect(t2, side, -(w - t2) / 2.0, 0.0),
            ];
            let j = 2.0 * t2 * t1 * (w - t2).powi(2) * (h - t1).powi(2)
                / (w * t2 + h * t1 - t2 * t2 - t1 * t1);
            (parts, j)
        }
        "I" => {
            let (h, wb, wt, tw, tb, tt) = (d[0], d[1], d[2], d[3], d[4], d[5]);
            if h <= tb + tt {
                return Err(bad("DIM1 > DIM5 + DIM6 is required"));
            }
            let web = h - tb - tt;
            let parts = vec![
                rect(wb, tb, 0.0, tb / 2.0),
                rect(tw, web, 0.0, tb + web / 2.0),
                rect(wt, tt, 0.0, h - tt / 2.0),
            ];
            let j = (wb * tb.powi(3) + wt * tt.powi(3) + (h - (tb + tt) / 2.0) * tw.powi(3)) / 3.0;
            (parts, j)
        }
        "CHAN" => {
            let (w, h, tw, tf) = (d[0], d[1], d[2], d[3]);
            if w <= tw || h <= 2.0 * tf {
                return Err(bad("DIM1 > DIM3 and DIM2 > 2·DIM4 are required"));
            }
            let flange = w - tw;
            let parts = vec![
                rect(tw, h, tw / 2.0, h / 2.0),
                rect(flange, tf, tw + flange / 2.0, tf / 2.0),
                rect(flange, tf, tw + flange / 2.0, h - tf / 2.0),
            ];
            let j = (2.0 * (w - tw / 2.0) * tf.powi(3) + (h - tf) * tw.powi(3)) / 3.0;
            (parts, j)
        }
        "T" => {
            let (w, h, tf, tw) = (d[0], d[1], d[2], d[3]);
            if h <= tf || w <= tw {
                return Err(bad("DIM2 > DIM3 and DIM1 > DIM4 are required"));
            }
            let web = h - tf;
            let parts = vec![
                rect(w, tf, 0.0, h - tf / 2.0),
                rect(tw, web, 0.0, web / 2.0),
            ];
            let j = (w * tf.powi(3) + (h - tf / 2.0) * tw.powi(3)) / 3.0;
            (parts, j)
        }
        "L" => {
            let (w, h, th, tv) = (d[0], d[1], d[2], d[3]);
            if h <= th || w <= tv {
                return Err(bad("DIM2 > DIM3 and DIM1 > DIM4 are required"));
            }
            let parts = vec![
                rect(w, th, w / 2.0, th / 2.0),
                rect(tv, h - th, tv / 2.0, th + (h - th) / 2.0),
            ];
            let j = ((w - tv / 2.0) * th.powi(3) + (h - th / 2.0) * tv.powi(3)) / 3.0;
            (parts, j)
        }
        _ => return Err(SectionError::UnsupportedType(shape.to_string())),
    };
    let (a, i1, i2, i12) = rectangles(&parts);
    Ok(SectionProperties { a, i1, i2, i12, j })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-30)
    }

    #[test]
    fn solid_shapes_match_closed_forms() {
        let r = library_section("ROD", &[0.1]).unwrap();
        assert!(close(r.a, std::f64::consts::PI * 0.01));
        assert!(close(r.j, r.i1 + r.i2));
        let b = library_section("BAR", &[0.02, 0.05]).unwrap();
        assert!(close(b.a, 0.001));
        assert!(close(b.i1, 0.02 * 0.05f64.powi(3) / 12.0));
        assert!(close(b.i2, 0.05 * 0.02f64.powi(3) / 12.0));
        assert_eq!(b.i12, 0.0);
        // square: J = 0.1406 a⁴ (Roark), the formula gives a⁴ (1/3 − 0.21·11/12) = 0.14083 a⁴
        let s = library_section("BAR", &[1.0, 1.0]).unwrap();
        assert!((s.j - 0.1406).abs() < 3e-4, "{}", s.j);
    }

    #[test]
    fn box_equals_outer_minus_inner_rectangle() {
        let (w, h, t1, t2) = (0.1, 0.2, 0.01, 0.015);
        let s = library_section("BOX", &[w, h, t1, t2]).unwrap();
        let (wi, hi) = (w - 2.0 * t2, h - 2.0 * t1);
        assert!(close(s.a, w * h - wi * hi));
        assert!(close(s.i1, (w * h.powi(3) - wi * hi.powi(3)) / 12.0));
        assert!(close(s.i2, (h * w.powi(3) - hi * wi.powi(3)) / 12.0));
    }

    #[test]
    fn symmetric_i_beam_matches_textbook() {
        // h = 0.3, flanges 0.15 × 0.01, web 0.006: I1 = (b h³ − (b − tw)(h − 2tf)³)/12
        let (h, b, tw, tf) = (0.3, 0.15, 0.006, 0.01);
        let s = library_section("I", &[h, b, b, tw, tf, tf]).unwrap();
        let i1 = (b * h.powi(3) - (b - tw) * (h - 2.0 * tf).powi(3)) / 12.0;
        assert!(close(s.i1, i1), "{} vs {i1}", s.i1);
        assert!(close(s.i12, 0.0) || s.i12.abs() < 1e-20);
    }

    #[test]
    fn angle_has_a_product_of_inertia_and_channel_has_none() {
        let l = library_section("L", &[0.05, 0.08, 0.005, 0.006]).unwrap();
        assert!(
            l.i12 < 0.0,
            "legs on +z and +y of the centroid corner: ∫yz < 0"
        );
        let c = library_section("CHAN", &[0.05, 0.1, 0.004, 0.006]).unwrap();
        assert!(c.i12.abs() < 1e-15 * c.i1);
    }

    #[test]
    fn refusals_name_the_shape() {
        let e = library_section("HAT", &[1.0; 4]).unwrap_err();
        assert!(e.to_string().contains("TYPE = HAT is not supported"), "{e}");
        let e = library_section("BOX", &[0.1, 0.1, 0.06, 0.01]).unwrap_err();
        assert!(e.to_string().contains("DIM2 > 2·DIM3"), "{e}");
        let e = library_section("TUBE", &[0.1]).unwrap_err();
        assert!(e.to_string().contains("needs 2 dimensions"), "{e}");
    }
}
