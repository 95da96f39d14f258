//! The waveform audit: reads back the VCD of a window unit (written by
//! `coopwin track --hdl rust-hdl --vcd`) with the `vcd` crate and checks it against the
//! coordinate sets the processor wrote and the window logic's rules (Appendix B):
//!
//! - every set the processor queued is taken over the handshake, byte for byte, in order (four
//!   bytes, or eight, high byte first, for a sensor over 256: [`Sample::wide`]);
//! - each frame delivers exactly the window of the set armed for it (the latest set complete
//!   at least `ARM_MARGIN` clocks before FVAL rises, each set used once): the right number of strobes,
//!   each on a line and column inside the window (on the 25% grid when decimated), in raster
//!   order; a frame with no set armed delivers nothing;
//! - the event order holds throughout: CRDY1 rises only while CSTRB1 is high and falls only
//!   while it is low; STRBEN rises only on the clock after FVAL rises; a pixel is strobed only
//!   while STRBEN was set on the clock before.
pub mod requests;
pub mod vcd;

pub use requests::Set;
pub use vcd::{read_vcd, Sample};

use coopwin_hdl::sim::camera::Window;

/// Clocks a set takes over the handshake (`hdl::run::writer_timing`'s latency) with margin:
/// a set queued later than this before the trace ends need not have been taken.
const TAKE_CLOCKS: usize = 32;

/// What the audit found.
#[derive(Clone, Debug, Default)]
pub struct Audit {
    /// Clocks read.
    pub clocks: usize,
    /// Frames seen (FVAL rising edges).
    pub frames: usize,
    /// Sets taken over the handshake.
    pub sets: usize,
    /// Windows delivered and verified.
    pub windows: usize,
    /// Every rule broken, with the clock.
    pub violations: Vec<String>,
}

/// Audits `samples` against the `requests` the processor wrote (in order, with the run clock
/// each was queued). A trace of chosen frames starts in the blanking before its first frame with
/// no set half-written: its requests are those not yet taken then, and the set pending then
/// (the first sample's START and set registers) arms like any other.
pub fn audit(samples: &[Sample], requests: &[(usize, Set)]) -> Audit {
    let mut a = Audit { clocks: samples.len(), ..Audit::default() };
    let first = samples.first().map_or(0, |s| s.clock as usize);
    let requests: Vec<(usize, Set)> = requests.iter().map(|r| (r.0.saturating_sub(first), r.1)).collect();
    let bad = |a: &mut Audit, t: usize, what: String| {
        if a.violations.len() < 50 {
            a.violations.push(format!("clock {t}: {what}"));
        }
    };
    // The handshake: bytes taken, sets completed.
    let per_coordinate = if samples.first().is_some_and(|s| s.wide) { 2 } else { 1 };
    let mut bytes: Vec<u32> = Vec::new();
    let mut complete: Vec<(usize, Set)> = Vec::new();
    let before = match samples.first() {
        Some(s) if s.start => {
            complete.push((0, s.pending));
            1
        }
        _ => 0,
    };
    for t in 1..samples.len() {
        let (s, p) = (&samples[t], &samples[t - 1]);
        if s.coord_ready && !p.coord_ready {
            if !s.coord_strobe {
                bad(&mut a, t, "CRDY1 rose with CSTRB1 low".into());
            }
            bytes.push(s.coord_data);
            if bytes.len() == 4 * per_coordinate {
                let c: Vec<u32> = bytes.chunks(per_coordinate).map(|b| b.iter().fold(0, |v, &byte| v << 8 | byte)).collect();
                let window = Window { xmin: c[0], xmax: c[1], ymin: c[2], ymax: c[3] };
                let set = Set { window, decimate: s.decimate };
                let n = complete.len() - before;
                match requests.get(n).map(|r| &r.1) {
                    Some(r) if *r == set => {}
                    Some(r) => bad(&mut a, t, format!("set {n} taken as {set}, the processor wrote {r}")),
                    None => bad(&mut a, t, format!("set {set} taken but never written")),
                }
                complete.push((t, set));
                bytes.clear();
            }
        }
        if !s.coord_ready && p.coord_ready && s.coord_strobe && p.coord_strobe {
            bad(&mut a, t, "CRDY1 fell with CSTRB1 still high".into());
        }
        let after_fval_rose = p.fval && !samples.get(t.wrapping_sub(2)).is_some_and(|q| q.fval);
        if s.strben && !p.strben && !after_fval_rose {
            bad(&mut a, t, "STRBEN rose other than on the clock after FVAL rose".into());
        }
        if s.pixel_strobe && !p.strben {
            bad(&mut a, t, "pixel strobed with STRBEN low".into());
        }
    }
    a.sets = complete.len() - before;
    let due = requests.iter().filter(|r| r.0 + TAKE_CLOCKS < samples.len()).count();
    if a.sets < due {
        let taken = a.sets;
        bad(&mut a, samples.len(), format!("{due} sets written in time to be taken, {taken} taken"));
    }
    // Frames: each delivers exactly its armed window.
    let starts: Vec<usize> = (1..samples.len()).filter(|&t| samples[t].fval && !samples[t - 1].fval).collect();
    a.frames = starts.len();
    let mut next_set = 0;
    for (i, &f) in starts.iter().enumerate() {
        let end = starts.get(i + 1).copied().unwrap_or(samples.len());
        // Invalid sets are refused: they arm nothing and cancel nothing.
        let armed = (next_set..complete.len()).rfind(|&k| complete[k].0 + coopwin_hdl::ARM_MARGIN <= f && complete[k].1.window.is_valid());
        let window = armed.map(|k| complete[k].1);
        if let Some(k) = armed {
            next_set = k + 1;
        }
        // Strobes in this frame and the bus position of the pixel each carries (one clock
        // earlier, so the position counted up to the previous clock): line = LVAL rises so
        // far in the frame, column = clocks since the rise.
        let (mut line, mut col) = (-1i64, 0i64);
        let mut got: Vec<(i64, i64)> = Vec::new();
        for t in f..end {
            let s = &samples[t];
            if s.pixel_strobe {
                got.push((line, col));
            }
            if s.lval && !samples[t - 1].lval && s.fval {
                line += 1;
                col = 0;
            } else {
                col += 1;
            }
        }
        match window {
            None if !got.is_empty() => bad(&mut a, f, format!("{} pixels strobed in a frame with no set armed", got.len())),
            None => {}
            Some(set) => {
                let Window { xmin: x0, xmax: x1, ymin: y0, ymax: y1 } = set.window;
                let step = if set.decimate { 2 } else { 1 };
                let want: Vec<(i64, i64)> = (y0..=y1)
                    .step_by(step)
                    .flat_map(|y| (x0..=x1).step_by(step).map(move |x| (i64::from(y), i64::from(x))))
                    .collect();
                if got != want {
                    let first = got.iter().zip(&want).position(|(g, w)| g != w);
                    bad(&mut a, f, format!(
                        "frame {i}: window {set} delivered {} pixels, expected {}; first wrong (line, column): {:?}",
                        got.len(),
                        want.len(),
                        first.map(|k| got[k])
                    ));
                } else {
                    a.windows += 1;
                }
            }
        }
    }
    a
}
