//! The banded linear solves of the chain's refinements: a joint's unknowns reach only the two
//! segments that meet there, so the normal equations of a chain are banded.

pub(crate) mod band;
pub(crate) mod band_lu;
pub(crate) mod damping;
