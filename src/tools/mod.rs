//! Tools around rendering: generated test scenes (and later image
//! comparison, convergence runs, BCSDF maps).

pub mod bcsdf;
pub mod curvegen;
pub mod imgdiff;
