//! The cross-referenced, validated model built from a [`Deck`](crate::deck::Deck).

pub mod mesh;

pub use mesh::{ElementBlock, MeshArrays};
