//! The window processors of the thesis's windowing strategies (2.3, 2.5, 4.2) as event-driven
//! state machines: each is handed the pixels of the window it asked for, or a message from
//! another processor, and answers with a [`Step`]: the kernel work it did (for a cost model),
//! the window it wants next, the messages it sends and the position it reports.
//!
//! - [`Watch`]: image differencing over a whole frame or a strip (2.4), reporting motion;
//! - [`Peripheral`]: SSD at 25% resolution to locate the target approximately, growing its
//!   window (40x40, then 64x64) when it fails (Detection mode, Table 2.2);
//! - [`Foveal`]: NCC (or the corner detector) at full resolution for accurate tracking; in
//!   COOP a second Foveal window runs the other algorithm on the same coordinates and the
//!   least-squares confidence measure picks the result each frame (4.3);
//! - [`CornerPartner`]: COOP's second Foveal processor, the corner detector on its master's
//!   coordinates (4.2);
//! - [`Spmf`]: the single processor that runs Watch, Detection and Tracking in turn (2.3.1).
//!
//! The hardware is reached only through the [`Step`]s: the caller (a board's main loop, or the
//! testbench's simulation) turns requests into coordinate writes
//! ([`crate::ports::window::CoordinateWriter`]) and messages into link traffic
//! ([`crate::ports::link::FramedLink`]); the testbench does both through these same types.
//!
//! One file a processor; [`messages`], [`template`], [`params`] and [`step`] are what they
//! share, and [`coop`] the COOP master's decision.
pub mod adapt;
pub mod coop;
pub mod foveal;
pub mod messages;
pub mod params;
pub mod partner;
pub mod peripheral;
pub mod spmf;
pub mod step;
pub mod template;
#[cfg(test)]
mod testing;
pub mod watch;

pub use coop::Policy;
pub use foveal::{Foveal, FovealKind};
pub use messages::{Dest, Msg};
pub use params::{FovealParams, Params, PeripheralParams};
pub use partner::CornerPartner;
pub use peripheral::Peripheral;
pub use spmf::Spmf;
pub use step::{Fix, Mode, Outcome, Step, Work};
pub use template::{Template, MAX_TEMPLATE};
pub use watch::Watch;
