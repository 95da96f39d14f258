//! The waveform audit: reads back the VCD of a window unit (written by
//! `coopwin track --hdl rust-hdl --vcd`) with the `vcd` crate and checks it against the
//! coordinate sets the processor wrote and the window logic's rules (Appendix B, issue #2):
//!
//! - every set the processor queued is taken over the handshake, byte for byte, in order;
//! - each frame delivers exactly the window of the set armed for it (the latest set complete
//!   at least 2 clocks before FVAL rises, each set used once): the right number of strobes,
//!   each on a line and column inside the window (on the 25% grid when decimated), in raster
//!   order; a frame with no set armed delivers nothing;
//! - the event order holds throughout: CRDY1 rises only while CSTRB1 is high and falls only
//!   while it is low; STRBEN rises only on the clock after FVAL rises; a pixel is strobed only
//!   while STRBEN was set on the clock before.
use std::collections::HashMap;
use std::io::BufRead;
use vcd::{Command, IdCode, ScopeItem, Value};

/// One clock of the unit, as the VCD has it after the rising edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sample {
    /// FVAL input.
    pub fval: bool,
    /// LVAL input.
    pub lval: bool,
    /// CSTRB1 input.
    pub coord_strobe: bool,
    /// Port 1 data input.
    pub coord_data: u32,
    /// Decimation input.
    pub decimate: bool,
    /// CRDY1.
    pub coord_ready: bool,
    /// CSTRB4.
    pub pixel_strobe: bool,
    /// STRBEN flag.
    pub strben: bool,
    /// Run clock of the sample (the VCD's timestamps are run clocks, traced span or not).
    pub clock: u64,
    /// START flag: a set is pending for the coming frame.
    pub start: bool,
    /// The pending set (the port's set registers).
    pub pending: Set,
}

/// A coordinate set the processor queued: (xmin, xmax, ymin, ymax, decimate).
pub type Set = (u32, u32, u32, u32, bool);

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

const SIGNALS: [&str; 14] = [
    "fval",
    "lval",
    "coord_strobe",
    "coord_data",
    "decimate",
    "coord_ready",
    "pixel_strobe",
    "strben.q",
    "start.q",
    "port.set_xn.q",
    "port.set_xx.q",
    "port.set_yn.q",
    "port.set_yx.q",
    "port.set_dec.q",
];

/// Reads the per-clock samples of window unit `unit` (traced as `uut$unit`) in a VCD.
pub fn read_vcd(reader: impl BufRead, unit: usize) -> Result<Vec<Sample>, String> {
    let mut parser = vcd::Parser::new(reader);
    let header = parser.parse_header().map_err(|e| format!("not a VCD: {e}"))?;
    let scope_name = format!("uut${unit}");
    let top = header
        .items
        .iter()
        .find_map(|i| match i {
            ScopeItem::Scope(s) if s.identifier == scope_name => Some(s),
            _ => None,
        })
        .ok_or_else(|| format!("the VCD has no `{scope_name}` scope (write it with coopwin track --hdl rust-hdl --vcd)"))?;
    let mut ids: HashMap<IdCode, usize> = HashMap::new();
    let mut clock_id = None;
    for (k, name) in SIGNALS.iter().enumerate() {
        let path: Vec<&str> = name.split('.').collect();
        let mut scope = top;
        for part in &path[..path.len() - 1] {
            scope = scope
                .items
                .iter()
                .find_map(|i| match i {
                    ScopeItem::Scope(s) if s.identifier == *part => Some(s),
                    _ => None,
                })
                .ok_or_else(|| format!("the VCD lacks uut.{name}"))?;
        }
        let leaf = path[path.len() - 1];
        let var = scope.find_var(leaf).ok_or_else(|| format!("the VCD lacks uut.{name}"))?;
        ids.insert(var.code, k);
    }
    if let Some(v) = top.find_var("clock") {
        clock_id = Some(v.code);
    }
    let clock_id = clock_id.ok_or("the VCD lacks uut.clock")?;
    let mut cur = Sample::default();
    let mut clock_high = false;
    let mut out = Vec::new();
    let mut started = false;
    let mut time = 0;
    for cmd in parser {
        let cmd = cmd.map_err(|e| format!("bad VCD: {e}"))?;
        match cmd {
            Command::Timestamp(t) => {
                if started && clock_high {
                    out.push(Sample { clock: time / coopwin_hdl::sim::vcd::VCD_CLOCK_PS, ..cur });
                }
                started = true;
                time = t;
            }
            Command::ChangeScalar(id, v) => {
                let b = v == Value::V1;
                if id == clock_id {
                    clock_high = b;
                }
                match ids.get(&id) {
                    Some(0) => cur.fval = b,
                    Some(1) => cur.lval = b,
                    Some(2) => cur.coord_strobe = b,
                    Some(4) => cur.decimate = b,
                    Some(5) => cur.coord_ready = b,
                    Some(6) => cur.pixel_strobe = b,
                    Some(7) => cur.strben = b,
                    Some(8) => cur.start = b,
                    Some(13) => cur.pending.4 = b,
                    _ => {}
                }
            }
            Command::ChangeVector(id, v) => {
                let n = v.iter().fold(0u32, |acc, b| (acc << 1) | u32::from(b == Value::V1));
                match ids.get(&id) {
                    Some(3) => cur.coord_data = n,
                    Some(9) => cur.pending.0 = n,
                    Some(10) => cur.pending.1 = n,
                    Some(11) => cur.pending.2 = n,
                    Some(12) => cur.pending.3 = n,
                    _ => {}
                }
            }
            _ => {}
        }
    }
    if started && clock_high {
        out.push(Sample { clock: time / coopwin_hdl::sim::vcd::VCD_CLOCK_PS, ..cur });
    }
    Ok(out)
}

/// Reads a requests CSV (`unit,clock,xmin,xmax,ymin,ymax,decimate`) written beside the VCD:
/// unit `unit`'s (clock queued, set) pairs.
pub fn read_requests(text: &str, unit: usize) -> Result<Vec<(usize, Set)>, String> {
    let mut out = Vec::new();
    for (i, l) in text.lines().enumerate().skip(1) {
        let f: Vec<u32> = l
            .split(',')
            .map(|v| v.trim().parse::<u32>().map_err(|_| format!("requests line {}: '{v}' is not a number", i + 1)))
            .collect::<Result<_, _>>()?;
        match f[..] {
            [u, t, a, b, c, d, e] if u as usize == unit => out.push((t as usize, (a, b, c, d, e != 0))),
            [_, _, _, _, _, _, _] => {}
            _ => return Err(format!("requests line {}: expected 7 fields", i + 1)),
        }
    }
    Ok(out)
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
            if bytes.len() == 4 {
                let set = (bytes[0], bytes[1], bytes[2], bytes[3], s.decimate);
                let n = complete.len() - before;
                match requests.get(n).map(|r| &r.1) {
                    Some(r) if *r == set => {}
                    Some(r) => bad(&mut a, t, format!("set {n} taken as {set:?}, the processor wrote {r:?}")),
                    None => bad(&mut a, t, format!("set {set:?} taken but never written")),
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
        let valid = |s: &Set| s.0 < s.1 && s.2 < s.3;
        let armed = (next_set..complete.len()).rfind(|&k| complete[k].0 + coopwin_hdl::ARM_MARGIN <= f && valid(&complete[k].1));
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
            Some((x0, x1, y0, y1, dec)) => {
                let step = if dec { 2 } else { 1 };
                let want: Vec<(i64, i64)> = (y0..=y1)
                    .step_by(step)
                    .flat_map(|y| (x0..=x1).step_by(step).map(move |x| (i64::from(y), i64::from(x))))
                    .collect();
                if got != want {
                    let first = got.iter().zip(&want).position(|(g, w)| g != w);
                    bad(&mut a, f, format!(
                        "frame {i}: window {:?} delivered {} pixels, expected {}; first wrong (line, column): {:?}",
                        (x0, x1, y0, y1, dec),
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
