//! Stresses and element forces from recovered strains: shell resultants, PSHELL fibre stresses,
//! solid stresses and the von Mises equivalents.
//!
//! **Shell element forces** (per unit length, at the centroid, in the element material system of
//! [`crate::fe::shell`], the system the shell strains are reported in): with the reference-plane
//! strains ε⁰, curvatures κ and transverse shear strains γ of [`ShellStrains`] and the section of
//! [`crate::fe::laminate`] (thesis eq. 2.7–2.9),
//!
//! ```text
//! N = A ε⁰ + B κ    [Nx Ny Nxy] = ∫σ dz
//! M = B ε⁰ + D κ    [Mx My Mxy] = ∫σ z dz  (z from the reference plane: Mx > 0 stretches z > 0)
//! Q = S γ           [Qx Qy]     = ∫[τxz τyz] dz
//! ```
//!
//! **PSHELL fibre stresses** from those resultants, as Nastran's PSHELL defines them: with the
//! mid-surface at z₀ = ZOFFS and M_mid = M − z₀N its moments,
//! σ(z) = N/T + M_mid (z − z₀)/I, I = (12I/T³)·T³/12; a PSHELL without MID2 has σ = N/T (membrane
//! only). For MID1 = MID2 without MID4 this is σ = Q ε(z) exactly.
//!
//! **Solids**: σ = λ tr(ε) 𝟏 + 2μ ε (MAT1, Lamé constants of [`Isotropic::lame`]), engineering
//! shear strains in, shear stresses out, order [σxx σyy σzz τxy τyz τzx].
//!
//! **von Mises**: plane stress √(σx² − σxσy + σy² + 3τxy²); 3-D
//! √(½[(σxx−σyy)² + (σyy−σzz)² + (σzz−σxx)²] + 3(τxy² + τyz² + τzx²)).

use super::laminate::{PshellSection, ShellSection};
use super::shell::ShellStrains;
use super::solid::Isotropic;

/// Element forces of a shell per unit length (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellForces {
    /// [Nx, Ny, Nxy].
    pub membrane: [f64; 3],
    /// [Mx, My, Mxy] about the reference plane.
    pub moment: [f64; 3],
    /// [Qx, Qy].
    pub shear: [f64; 2],
}

impl ShellForces {
    /// The eight values in Nastran's order: Nx Ny Nxy Mx My Mxy Qx Qy.
    pub fn row(&self) -> [f64; 8] {
        let (n, m, q) = (self.membrane, self.moment, self.shear);
        [n[0], n[1], n[2], m[0], m[1], m[2], q[0], q[1]]
    }
}

fn mul3(a: &[[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i][0] * x[0] + a[i][1] * x[1] + a[i][2] * x[2])
}

/// N = Aε⁰ + Bκ, M = Bε⁰ + Dκ, Q = Sγ of `section` for the centroid strains `e`.
pub fn shell_forces(section: &ShellSection, e: &ShellStrains) -> ShellForces {
    let (n1, n2) = (mul3(&section.a, e.membrane), mul3(&section.b, e.curvature));
    let (m1, m2) = (mul3(&section.b, e.membrane), mul3(&section.d, e.curvature));
    let s = &section.s;
    ShellForces {
        membrane: std::array::from_fn(|i| n1[i] + n2[i]),
        moment: std::array::from_fn(|i| m1[i] + m2[i]),
        shear: [
            s[0][0] * e.shear[0] + s[0][1] * e.shear[1],
            s[1][0] * e.shear[0] + s[1][1] * e.shear[1],
        ],
    }
}

/// [σx, σy, τxy] of a PSHELL at the fibre `z` (from the reference plane) for its forces `f`:
/// N/T + M_mid (z − z₀)/I (module doc).
pub fn pshell_fibre_stress(p: &PshellSection, f: &ShellForces, z: f64) -> [f64; 3] {
    let membrane = f.membrane.map(|n| n / p.t);
    if p.bending.is_none() {
        return membrane;
    }
    let inertia = p.bending_ratio * p.t.powi(3) / 12.0;
    std::array::from_fn(|i| {
        membrane[i] + (f.moment[i] - p.zoffs * f.membrane[i]) * (z - p.zoffs) / inertia
    })
}

/// Plane-stress von Mises stress of [σx, σy, τxy].
pub fn von_mises_plane(s: [f64; 3]) -> f64 {
    (s[0] * s[0] - s[0] * s[1] + s[1] * s[1] + 3.0 * s[2] * s[2]).sqrt()
}

/// [σxx, σyy, σzz, τxy, τyz, τzx] of an isotropic solid for engineering strains `e` (same order).
pub fn solid_stress(m: Isotropic, e: &[f64; 6]) -> [f64; 6] {
    let l = m.lame();
    let tr = e[0] + e[1] + e[2];
    std::array::from_fn(|i| {
        if i < 3 {
            l.lambda * tr + 2.0 * l.mu * e[i]
        } else {
            l.mu * e[i]
        }
    })
}

/// Von Mises stress of [σxx, σyy, σzz, τxy, τyz, τzx].
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let d = (s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2);
    (0.5 * d + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::laminate::RoleMaterial;

    fn strains(membrane: [f64; 3], curvature: [f64; 3]) -> ShellStrains {
        ShellStrains {
            membrane,
            curvature,
            top: [0.0; 3],
            bottom: [0.0; 3],
            shear: [1e-4, -2e-4],
            axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
    }

    /// A homogeneous PSHELL: the fibre stress from the resultants is Q ε(z), with and without a
    /// ZOFFS (the fibre strain ε⁰ + zκ is about the reference plane in both).
    #[test]
    fn pshell_fibre_stress_is_the_plane_stress_law_at_the_fibre() {
        let (e, nu, t) = (70e9, 0.3, 0.004);
        for zoffs in [0.0, 0.0015] {
            let p = PshellSection {
                zoffs,
                ..PshellSection::homogeneous(RoleMaterial::mat1(1, e, nu, 2700.0), t)
            };
            let section = ShellSection::pshell(&p).unwrap();
            let s = strains([1e-4, -3e-5, 2e-5], [0.02, -0.01, 0.005]);
            let f = shell_forces(&section, &s);
            let q = e / (1.0 - nu * nu);
            for z in [zoffs - t / 2.0, zoffs + t / 2.0, zoffs + 0.3 * t] {
                let eps: [f64; 3] = std::array::from_fn(|i| s.membrane[i] + z * s.curvature[i]);
                let want = [
                    q * (eps[0] + nu * eps[1]),
                    q * (eps[1] + nu * eps[0]),
                    e / (2.0 * (1.0 + nu)) * eps[2],
                ];
                let got = pshell_fibre_stress(&p, &f, z);
                for i in 0..3 {
                    assert!(
                        (got[i] - want[i]).abs() < 1e-9 * q * 1e-4,
                        "{got:?} {want:?}"
                    );
                }
            }
            let g = e / (2.0 * (1.0 + nu));
            assert!((f.shear[0] - 5.0 / 6.0 * g * t * 1e-4).abs() < 1e-9 * g * t * 1e-4);
        }
    }

    #[test]
    fn von_mises_of_uniaxial_and_pure_shear() {
        assert!((von_mises_plane([100.0, 0.0, 0.0]) - 100.0).abs() < 1e-12);
        assert!((von_mises_plane([0.0, 0.0, 10.0]) - 10.0 * 3f64.sqrt()).abs() < 1e-12);
        assert!((von_mises(&[100.0, 0.0, 0.0, 0.0, 0.0, 0.0]) - 100.0).abs() < 1e-12);
        assert!((von_mises(&[5.0, 5.0, 5.0, 0.0, 0.0, 0.0])).abs() < 1e-12);
        assert!((von_mises(&[0.0, 0.0, 0.0, 0.0, 10.0, 0.0]) - 10.0 * 3f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn solid_stress_of_uniaxial_strain_state() {
        let m = Isotropic { e: 200e9, nu: 0.3 };
        // uniaxial stress σ along x: ε = σ/E (1, −ν, −ν)
        let s = solid_stress(m, &[1e-3, -3e-4, -3e-4, 0.0, 0.0, 0.0]);
        assert!((s[0] - 200e6).abs() < 1e-3);
        assert!(s[1].abs() < 1e-3 && s[2].abs() < 1e-3);
        let shear = solid_stress(m, &[0.0, 0.0, 0.0, 0.0, 0.0, 1e-3]);
        assert!((shear[5] - 200e9 / 2.6 * 1e-3).abs() < 1e-3);
    }
}
