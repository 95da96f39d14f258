//! Ctrl-C during a long run (`coopwin track`): the signal only raises a flag; the frame
//! sources check it before each frame and end the run with [`FrameError::Interrupted`], so
//! the outputs' streams are dropped unfinished (their temporary files removed, the files they
//! would replace left as they were) and the program exits with code 130.
use crate::frames::{FrameError, FrameSource};
use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

extern "C" fn on_sigint(_: libc::c_int) {
    // Async-signal-safe: one atomic store.
    INTERRUPTED.store(true, Ordering::SeqCst);
}

/// From now on, SIGINT (Ctrl-C) raises the flag instead of ending the process at once.
pub fn install() {
    // SAFETY: the handler only stores to an atomic, which is async-signal-safe.
    unsafe {
        libc::signal(libc::SIGINT, on_sigint as extern "C" fn(libc::c_int) as libc::sighandler_t);
    }
}

/// True once Ctrl-C was pressed.
pub fn requested() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// A frame source that stops handing out frames once its second field says so: Ctrl-C
/// ([`requested`]) for the CLI, the caller gone for the Python package.
pub struct Interruptible<'a>(pub &'a mut dyn FrameSource, pub &'a dyn Fn() -> bool);

impl FrameSource for Interruptible<'_> {
    fn size(&self) -> (usize, usize) {
        self.0.size()
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        if (self.1)() {
            return Err(FrameError::Interrupted);
        }
        self.0.frame(k)
    }
}
