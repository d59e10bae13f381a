//! HDF5 and XDMF output (in progress).
