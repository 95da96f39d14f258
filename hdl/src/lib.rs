//! Window logic of the cooperative-windowing tracker (thesis 2.2, Appendices A and B) in
//! rust-hdl: the blocks, their Verilog export, a camera raster generator and a fast driver.
//!
//! Data flows camera -> [`WindowUnit`] -> processor: [`camera`] produces the CA-D1's raster,
//! [`driver`] steps the rust-hdl blocks clock by clock, [`verilog`] exports `window_unit` and
//! `window_network`.
pub mod appendix_b;
pub mod camera;
pub mod coord_port;
pub mod driver;
pub mod reg;
pub mod run;
pub mod sim { pub mod verilator; }
pub mod verilog;
pub mod window_unit;

pub use coord_port::CoordPort;
pub use window_unit::WindowUnit;

/// Counter and coordinate width of the thesis's 256x256 camera.
pub const CA_D1_BITS: usize = 8;
