//! The firmware's benchmark suite as text, for bit-exact comparison between the host and a
//! Cortex-M4 (thesis 2.6: the tracking code runs on the processors next to the window
//! logic; 4.2-4.3: the COOP Foveal pair and its decision).
//!
//! [`suite::run`] runs every kernel on the benchmark inputs of `fixtures/bench/` and the
//! COOP Foveal pair on a window stream recorded from the testbench (`fixtures/board/`), and
//! writes one line per result with every float as its IEEE bits. The host test and the board
//! binary call the same function, so the lines can differ only if the arithmetic does.
//! A [`suite::Meter`] brackets each kernel; the board's meter counts instructions, the
//! host's does nothing.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod pgm;
pub mod stream;
pub mod suite;
