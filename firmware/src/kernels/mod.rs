//! The tracking kernels (thesis 2.4, ch. 3, 3.4.1, 4.3, 5.2): pure functions and small
//! fixed-capacity state over borrowed pixel views, with typed errors and no panics.
//!
//! * [`view`]: window views, including the 25 % (decimated) view;
//! * [`motion`]: image differencing for the Watch window (2.4);
//! * [`matching`]: SSD / SAD / NCC (2.4) and zero-mean NCC, with sub-pixel refinement;
//! * [`refine`]: Lucas-Kanade refinement of a match, beyond the parabola's accuracy;
//! * [`warp`]: Lucas-Kanade alignment under a similarity warp (turn and scale);
//! * [`support`]: the object's part of a corner template, and NCC over it alone;
//! * [`corner`]: the window-based corner detector (ch. 3);
//! * [`info`]: information content measures (3.4.1);
//! * [`confidence`]: the least-squares window confidence measure (4.3) and a Kalman-filter
//!   policy (5.2);
//! * [`fmath`]: the FPU's square root (and `dsp`, the DSP extension's dual multiply-add, for
//!   the matching), through `asm!` on the Cortex-M4F and portable elsewhere; [`x86`], which of
//!   x86-64's wider vector extensions the host has and the kernels use.
pub mod confidence;
pub mod corner;
#[cfg(any(test, target_arch = "arm"))]
mod dsp;
pub mod fmath;
pub mod info;
pub mod matching;
pub mod motion;
pub mod refine;
pub mod support;
pub mod view;
pub mod warp;
#[cfg(target_arch = "x86_64")]
pub mod x86;
