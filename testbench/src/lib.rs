//! The coopwin testbench: the camera, the window units and the processors simulated together,
//! and the `coopwin` command that runs them.
pub mod audit;
pub mod backend;
pub mod board_stream;
pub mod commands;
pub mod cost;
pub mod experiments;
pub mod metrics;
pub mod plot;
pub mod real_images;
pub mod report;
pub mod scene;
pub mod system;
pub mod timing_svg;
pub mod verilator;
