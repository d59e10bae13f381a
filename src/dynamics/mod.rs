//! Frequency and time response (thesis §2.4; DESIGN.md §2).
//!
//! - [`frf`]: receptance of a dense (reduced) model, H(ω) = S_out (K − ω²M + iωC)⁻¹ S_in.

pub mod frf;
