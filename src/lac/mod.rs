//! Log-aesthetic curves.
