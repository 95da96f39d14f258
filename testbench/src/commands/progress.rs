//! Progress of a long run on standard error.
use std::io::IsTerminal;

/// Seconds between two progress lines when standard error is not a terminal (a log file, a
/// pipe): a long run shows it is alive without filling the log. `COOPWIN_PROGRESS_SECS`
/// sets another.
const LOG_PROGRESS_SECS: f64 = 5.0;

/// A progress line on stderr: frames done, frames/s (wall-clock) and the time left; on a
/// terminal redrawn in place at most four times a second, elsewhere a line every
/// [`LOG_PROGRESS_SECS`].
pub fn progress_line(total: usize, label: &'static str) -> impl FnMut(usize) {
    let tty = std::io::stderr().is_terminal();
    let log_secs = std::env::var("COOPWIN_PROGRESS_SECS").ok().and_then(|v| v.parse::<f64>().ok()).filter(|s| s.is_finite() && *s >= 0.0);
    let every = if tty { 0.25 } else { log_secs.unwrap_or(LOG_PROGRESS_SECS) };
    let started = std::time::Instant::now();
    let mut shown = started;
    move |k: usize| {
        let now = std::time::Instant::now();
        let last = k + 1 == total;
        let due = now.duration_since(shown).as_secs_f64() >= every;
        if !(due || (last && tty)) {
            return;
        }
        shown = now;
        let rate = (k + 1) as f64 / now.duration_since(started).as_secs_f64().max(1e-9);
        let left = (total - k - 1) as f64 / rate.max(1e-9);
        let line = format!("{label}: frame {}/{total}, {rate:.0} frames/s, ETA {}:{:02}", k + 1, left as u64 / 60, left as u64 % 60);
        if tty {
            eprint!("\r{line}   ");
            if last {
                eprintln!();
            }
        } else {
            eprintln!("{line}");
        }
    }
}
