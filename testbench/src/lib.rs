//! The coopwin testbench: the camera, the window units and the processors simulated together,
//! and the `coopwin` command that runs them.
//!
//! Data flows one way, and so do the modules' dependencies:
//!
//! ```text
//! frames  ->  units  ->  system  ->  analysis  ->  report  ->  tracking  ->  experiments  ->  commands
//! (camera)   (window     (firmware    (metrics,     (tables,    (a run of     (tables and     (the CLI)
//!             logic)      processors)  audit)        CSV, SVG)   track's       figures)
//!                                                                options)
//! ```
//!
//! - [`frames`]: frames from a folder, the synthetic scene, and the ground truth;
//! - [`units`]: the window units (behavioural model, rust-hdl, Verilator) that cut windows;
//! - [`system`]: the processors and their links in simulated time;
//! - [`analysis`]: tracking figures against ground truth, and the waveform audit;
//! - [`report`]: summaries, CSV files, charts and timing diagrams;
//! - [`tracking`]: a run of `coopwin track`'s options, which the CLI and the Python package share;
//! - [`experiments`]: the thesis's tables and figures, and the real-image evaluation;
//! - [`commands`]: the `coopwin` subcommands;
//! - [`board_stream`]: the window stream the Cortex-M4 board replays.
#![warn(missing_docs)]

/// `From` impls that wrap each inner error as a variant of an error enum:
/// `wrap_errors!(Outer { Variant(Inner), ... })`.
macro_rules! wrap_errors {
    ($outer:ident { $($variant:ident($inner:ty)),* $(,)? }) => {
        $(impl From<$inner> for $outer {
            fn from(e: $inner) -> Self {
                $outer::$variant(e)
            }
        })*
    };
}

pub mod analysis;
pub mod board_stream;
pub mod commands;
pub mod experiments;
pub mod frames;
pub mod report;
pub mod system;
pub mod tracking;
pub mod units;
