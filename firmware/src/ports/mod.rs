//! The processor's ports to the hardware (thesis 2.2, 2.6): the processors reach the window
//! unit, the other processors and the robot controller only through these, so a board port
//! is wiring and the testbench can simulate.
//!
//! * [`window`]: a window unit's coordinate port (a [`crate::types::WindowRequest`] written as
//!   four bytes over the four-phase handshake) and pixel port; [`hal_pins`]: the same on
//!   `embedded-hal` digital pins;
//! * [`link`]: the processors' messages ([`crate::processors::Msg`]) on a byte stream;
//! * [`position`]: position updates for the robot controller;
//! * [`frame`]: the framing both byte links use, and [`payload`] the fields inside a frame.
pub mod frame;
pub mod hal_pins;
pub mod link;
pub mod payload;
pub mod position;
pub mod window;
