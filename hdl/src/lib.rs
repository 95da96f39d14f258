//! Window logic of the cooperative-windowing tracker (thesis 2.2, Appendices A and B) in
//! rust-hdl.
//!
//! The synthesizable blocks and their Verilog export are at the top: [`window_unit`] (one
//! windowing unit, Figs. 2.3, A1.1, A1.2), [`coord_port`] (its coordinate input section),
//! [`reg`] (the D flip-flop they are built of) and [`verilog`] (the readable, parametric
//! `window_unit` of `rtl/window_unit.v`, the same registers as these blocks, and
//! `window_network`). [`sim`] holds what only simulates them: the camera raster, the drivers
//! that step them, the Appendix B runs and the waveforms.
//!
//! Data flows camera -> [`WindowUnit`] -> processor.
#![warn(missing_docs)]

pub mod coord_port;
pub mod reg;
pub mod sim;
pub mod verilog;
pub mod window_unit;

pub use coord_port::CoordPort;
pub use window_unit::{WindowUnit, ARM_MARGIN};

/// Counter and coordinate width of the thesis's 256x256 camera.
pub const CA_D1_BITS: usize = 8;

/// Pixel width of the thesis's camera.
pub const CA_D1_PIXEL_BITS: usize = 8;

/// The window unit of the thesis's CA-D1: 256x256, 8-bit pixels.
pub type CaD1Unit = WindowUnit<CA_D1_BITS, CA_D1_PIXEL_BITS>;
