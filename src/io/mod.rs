//! HDF5 and XDMF output (DESIGN.md §8).
//!
//! - [`hdf5_file`]: [`OutputFile`], written under a temporary name and renamed on commit, plus
//!   typed dataset/attribute helpers and the [`IoError`] type.
//! - [`model_group`]: [`write_model`] fills `/model` from [`MeshArrays`](crate::model::MeshArrays).
//! - [`xdmf`]: [`write_xdmf`] writes `<out>.xdmf` next to the HDF5 file for ParaView.
//! - [`prom_group`]: [`write_prom`] / [`read_prom`] for the `/prom` group of a pROM artifact.
//! - [`pfmb_group`]: [`write_pfmb`] / [`read_pfmb`] for the `/pfmb` group of a `SOL FMB` run.
//! - [`matrix_market`], [`prom_lsq`]: sampled matrices from another FE code and the manifest of
//!   the least-squares route (`paraflex prom-lsq`).
//! - [`csv_table`]: two columns of a CSV file (TABLEF).
//! - [`info`]: [`describe`] summarises any paraflex HDF5 file (`paraflex info`).

pub mod csv_table;
pub mod hdf5_file;
pub mod info;
pub mod matrix_market;
pub mod model_group;
pub mod pfmb_group;
pub mod prom_group;
pub mod prom_lsq;
pub mod xdmf;

pub use hdf5_file::{
    IoError, OutputFile, SCHEMA_VERSION, set_attr_f64, set_attr_f64s, set_attr_i64, set_attr_str,
    set_attr_strings, temp_path_for, write_c64, write_f64, write_mat, write_rows3, write_strings,
    write_u32,
};
pub use info::{
    DatasetSummary, FileSummary, ModalResultSummary, ModelSummary, PromSummary, ResultSummary,
    describe,
};
pub use model_group::{CONNECTIVITY_INDEXING, ModelInfo, read_grid_ids, write_model};
pub use pfmb_group::{PFMB_VERSION, read_pfmb, write_pfmb};
pub use prom_group::{
    PromBody, read_prom, read_prom_body, read_prom_inputs, read_prom_sensors, write_prom,
    write_prom_basis, write_prom_body,
};
pub use xdmf::{XdmfWritten, write_xdmf, xdmf_path_for};
