//! Simulation of the window logic (not synthesised): the camera's raster, the blocks stepped
//! clock by clock with the processor's coordinate writer on their port, the Appendix B
//! acquisition in rust-hdl's thread-based simulator, and VCD waveforms.
//!
//! * [`camera`]: the CA-D1's raster, clock by clock (thesis 2.2.1);
//! * [`driver`]: direct stepping of one unit or a network of units, and the processor's side of
//!   the coordinate port (the firmware's `CoordinateWriter`);
//! * [`run`]: a unit run end to end with every clock recorded, for replay in other simulators;
//! * [`appendix_b`]: the acquisition sequences of Appendix B (Figs. B1.1-B1.5);
//! * [`vcd`]: rust-hdl's VCD writer on a stepped unit.
pub mod appendix_b;
pub mod camera;
pub mod driver;
pub mod run;
pub mod vcd;
pub mod verilator;
