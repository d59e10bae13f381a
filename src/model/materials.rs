//! Materials as the element kernels read them ([`Model::material`]): MAT1 is isotropic
//! (E, G, ν, ρ with the missing one of E, G, ν derived on the card), MAT8 orthotropic in the
//! shell plane.

use super::{MaterialRef, Model};
use crate::card_values::PlyAllowables;

/// A material by the kind of its elasticity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// MAT1.
    Isotropic(IsotropicMaterial),
    /// MAT8.
    Orthotropic(OrthotropicMaterial),
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
    /// Mass density.
    pub fn rho(&self) -> f64 {
        match self {
            Material::Isotropic(m) => m.rho,
            Material::Orthotropic(m) => m.rho,
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
        })
    }
}
