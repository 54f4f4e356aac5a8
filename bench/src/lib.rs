//! rpbrt's benchmark harness: error-against-time runs of a scene
//! (`convergence`), and the performance report against pbrt-v4's figures
//! (`report`, with the dual model's overhead in `dual_overhead`) that
//! writes `docs/performance.md`, parse/build time and peak memory on a
//! generated curve file (`curves`), and whole renders at several thread
//! counts (`scaling`).
//!
//! It sits above the renderer: it renders through the `rpbrt` library
//! (in-process, for the timed convergence renders) and through the
//! `rpbrt` executable (child processes, for peak memory and the
//! dual-model pairs), and the renderer knows nothing of it. The `rpbrt`
//! binary's `report` and `convergence` subcommands run this crate's
//! `rpbrt-bench` executable (`rpbrt::tools::bench_handoff`).

pub mod child;
pub mod convergence;
pub mod curves;
pub mod dual_overhead;
pub mod error;
pub mod executable;
pub mod provenance;
pub mod report;
pub mod scaling;
pub mod steal;
pub mod template;

pub use error::{Error, Result};
