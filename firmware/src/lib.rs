//! Tracking firmware of the cooperative-windowing tracker (thesis ch. 2.3-4).
//!
//! `no_std`, no allocator, fixed capacities, and no panic on any input: every kernel is a
//! pure function over borrowed pixel views ([`view::WindowView`]) that returns a typed
//! error instead of failing. One module per algorithm family:
//!
//! * [`view`]: window views, including the 25 % (decimated) view;
//! * [`motion`]: image differencing for the Watch window (2.4);
//! * [`matching`]: SSD / SAD / NCC (2.4) and zero-mean NCC, with sub-pixel refinement;
//! * [`refine`]: Lucas-Kanade refinement of a match, beyond the parabola's accuracy;
//! * [`corner`]: the window-based corner detector (ch. 3);
//! * [`info`]: information content measures (3.4.1);
//! * [`confidence`]: the least-squares window confidence measure and COOP decision (4.3),
//!   and a Kalman-filter policy (5.2);
//! * [`guard`]: guarded cooperation, the COOP decision that follows the corner detector only
//!   where it measures the tracked point;
//! * [`tracker`]: the window processors (Watch, Peripheral, Foveal, SPMF);
//! * [`types`]: the shared vocabulary (points);
//! * [`ports`]: hardware traits and framed byte encodings over `embedded-io`;
//! * [`window_ports`]: the processor's side of a window unit's coordinate and pixel ports
//!   (2.2.1), and [`hal_pins`]: the same ports on `embedded-hal` digital pins.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(test)]
extern crate std;

/// Implements `Display`, one message per variant, and `core::error::Error` for a field-less
/// error enum, so callers can show a person what went wrong without `{:?}`.
macro_rules! error_messages {
    ($ty:ty { $($variant:ident => $msg:literal),* $(,)? }) => {
        impl core::fmt::Display for $ty {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str(match self { $(Self::$variant => $msg),* })
            }
        }
        impl core::error::Error for $ty {}
    };
}

pub mod confidence;
pub mod corner;
pub mod guard;
pub mod hal_pins;
pub mod window_ports;
pub mod info;
pub mod matching;
pub mod motion;
pub mod ports;
pub mod refine;
pub mod support;
pub mod tracker;
pub mod types;
pub mod view;
