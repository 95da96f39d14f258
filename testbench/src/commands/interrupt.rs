//! Ctrl-C during a long run (`coopwin track`): the signal only raises a flag; the frame
//! sources check it before each frame ([`Interruptible`](crate::frames::Interruptible)) and
//! end the run, so the outputs' streams are dropped unfinished (their temporary files
//! removed, the files they would replace left as they were) and the program exits with
//! code 130.
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
