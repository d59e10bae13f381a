//! Materials as the element kernels read them ([`Model::material`]): MAT1 is isotropic
//! (E, G, ν, ρ with the missing one of E, G, ν derived on the card), MAT8 orthotropic in the
//! shell plane, MAT2 anisotropic in the shell plane (its matrix given directly).

use super::{MaterialRef, Model};
use crate::card_values::PlyAllowables;

/// A material by the kind of its elasticity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// MAT1.
    Isotropic(IsotropicMaterial),
    /// MAT8.
    Orthotropic(OrthotropicMaterial),
    /// MAT2.
    Anisotropic(AnisotropicMaterial),
}

/// Plane-stress anisotropic elasticity and density (MAT2): {σ1 σ2 τ12} = G {ε1 ε2 γ12}.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnisotropicMaterial {
    /// The symmetric matrix G (order 1, 2, 12).
    pub g: [[f64; 3]; 3],
    pub rho: f64,
}

/// Isotropic elasticity and density (MAT1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsotropicMaterial {
    pub e: f64,
    pub g: f64,
    pub nu: f64,
    pub rho: f64,
}

/// Plane-stress orthotropic elasticity with transverse shear moduli, and density (MAT8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrthotropicMaterial {
    pub e1: f64,
    pub e2: f64,
    pub nu12: f64,
    pub g12: f64,
    /// Transverse shear moduli G1Z, G2Z (`None`: not given).
    pub g1z: Option<f64>,
    pub g2z: Option<f64>,
    pub rho: f64,
    /// Strength allowables (ply failure indices).
    pub allowables: PlyAllowables,
}

impl Material {
    /// The card that defines it.
    pub fn card(&self) -> &'static str {
        match self {
            Material::Isotropic(_) => "MAT1",
            Material::Orthotropic(_) => "MAT8",
            Material::Anisotropic(_) => "MAT2",
        }
    }

    /// Mass density.
    pub fn rho(&self) -> f64 {
        match self {
            Material::Isotropic(m) => m.rho,
            Material::Orthotropic(m) => m.rho,
            Material::Anisotropic(m) => m.rho,
        }
    }
}

impl Model {
    /// The material with id `mid`.
    pub fn material(&self, mid: u32) -> Option<Material> {
        Some(match *self.materials.get(&mid)? {
            MaterialRef::Mat1(i) => {
                let m = self.bulk.mat1.get(i)?;
                Material::Isotropic(IsotropicMaterial {
                    e: m.e,
                    g: m.g,
                    nu: m.nu,
                    rho: m.rho,
                })
            }
            MaterialRef::Mat8(i) => {
                let m = self.bulk.mat8.get(i)?;
                Material::Orthotropic(OrthotropicMaterial {
                    e1: m.e1,
                    e2: m.e2,
                    nu12: m.nu12,
                    g12: m.g12,
                    g1z: m.g1z,
                    g2z: m.g2z,
                    rho: m.rho,
                    allowables: m.allowables,
                })
            }
            MaterialRef::Mat2(i) => {
                let m = self.bulk.mat2.get(i)?;
                Material::Anisotropic(AnisotropicMaterial {
                    g: m.in_plane(),
                    rho: m.rho,
                })
            }
        })
    }
}

/// The thermal expansion of a material: the coefficients of the free thermal strain
/// {ε1 ε2 γ12} per degree in the material axes (MAT1: {A, A, 0}, MAT8: {A1, A2, 0}, MAT2:
/// {A1, A2, A3}) and the reference (stress-free) temperature TREF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Expansion {
    pub alpha: [f64; 3],
    pub tref: f64,
}

impl Model {
    /// The thermal expansion of material `mid`.
    pub fn expansion(&self, mid: u32) -> Option<Expansion> {
        Some(match *self.materials.get(&mid)? {
            MaterialRef::Mat1(i) => {
                let m = self.bulk.mat1.get(i)?;
                Expansion {
                    alpha: [m.a, m.a, 0.0],
                    tref: m.tref,
                }
            }
            MaterialRef::Mat8(i) => {
                let m = self.bulk.mat8.get(i)?;
                Expansion {
                    alpha: [m.a[0], m.a[1], 0.0],
                    tref: m.tref,
                }
            }
            MaterialRef::Mat2(i) => {
                let m = self.bulk.mat2.get(i)?;
                Expansion {
                    alpha: m.a,
                    tref: m.tref,
                }
            }
        })
    }
}
