//! Acceleration structures.

pub mod bvh;
pub mod child_test;
pub mod instance;
pub mod instruction_set;
pub mod parallel_build;
pub mod prefetch;
pub mod wide_conversion;

pub use bvh::Bvh;
pub use instruction_set::InstructionSet;
pub use prefetch::{prefetch, prefetch_address};
