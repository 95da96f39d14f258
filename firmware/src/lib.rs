//! Tracking firmware of the cooperative-windowing tracker (thesis ch. 2.3-4).
//!
//! `no_std`, no allocator, fixed capacities, and no panic on any input: every kernel is a
//! pure function over borrowed pixel views ([`kernels::view::WindowView`]) that returns a typed
//! error instead of failing. Four layers:
//!
//! * [`types`]: the shared vocabulary (points, window requests, the position's source);
//! * [`kernels`]: the image-processing and decision kernels (2.4, ch. 3, 4.3);
//! * [`processors`]: the window processors, Watch, Peripheral, Foveal and SPMF (2.3), as
//!   event-driven state machines, and the COOP decision (4.2-4.3);
//! * [`ports`]: the window unit's coordinate and pixel ports (2.2.1), the framed links
//!   between processors and to the robot controller.
//!
//! Dependencies go one way: `types` <- `kernels` <- `processors` <- `ports`.
#![no_std]
// Two exceptions, `kernels::fmath::sqrtf` and `kernels::dsp::smlad`: one instruction each
// through `asm!`.
#![deny(unsafe_code)]
#![warn(missing_docs)]

#[cfg(test)]
extern crate std;

/// Implements `Display`, one message per variant, and `core::error::Error` for an error enum,
/// so callers can show a person what went wrong without `{:?}`. A generic enum names its
/// type parameters, and a variant that wraps an inner error (`Io(e) => "..."`) prints the
/// message followed by the inner error's `Debug`.
macro_rules! error_messages {
    ($ty:ident<$($g:ident),+> { $($variant:ident $(($inner:ident))? => $msg:literal),* $(,)? }) => {
        impl<$($g: core::fmt::Debug),+> core::fmt::Display for $ty<$($g),+> {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                match self {
                    $(Self::$variant $(($inner))? => {
                        f.write_str($msg)?;
                        $(write!(f, ": {:?}", $inner)?;)?
                        Ok(())
                    })*
                }
            }
        }
        impl<$($g: core::fmt::Debug),+> core::error::Error for $ty<$($g),+> {}
    };
    ($ty:ty { $($variant:ident => $msg:literal),* $(,)? }) => {
        impl core::fmt::Display for $ty {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str(match self { $(Self::$variant => $msg),* })
            }
        }
        impl core::error::Error for $ty {}
    };
}

pub mod kernels;
pub mod ports;
pub mod processors;
pub mod types;
