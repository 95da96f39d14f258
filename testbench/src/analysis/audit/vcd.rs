//! Reading a window unit's VCD back (the `vcd` crate): one sample per clock of the signals the
//! audit checks, from the scope `uut$K` that `coopwin track --hdl rust-hdl --vcd` writes.
use super::requests::Set;
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
    /// Coordinates take two bytes, high first (eight-byte sets): the unit's set registers are
    /// wider than 8 bits, which the rust-hdl units are exactly when the sensor is wider or
    /// taller than 256 (`coopwin_hdl::sim::driver::stepped_widths`).
    pub wide: bool,
}

/// The signals read, in the order of the indices `read_vcd` matches on.
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

/// Why a VCD cannot be read.
#[derive(Debug)]
pub enum VcdError {
    /// The header is not a VCD's.
    NotVcd(std::io::Error),
    /// The unit's scope is missing.
    NoScope(String),
    /// A signal of the unit is missing (its path under the unit's scope).
    Lacks(&'static str),
    /// The value changes cannot be parsed.
    Bad(std::io::Error),
}

impl std::fmt::Display for VcdError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            VcdError::NotVcd(e) => write!(f, "not a VCD: {e}"),
            VcdError::NoScope(s) => write!(f, "the VCD has no `{s}` scope (write it with coopwin track --hdl rust-hdl --vcd)"),
            VcdError::Lacks(name) => write!(f, "the VCD lacks uut.{name}"),
            VcdError::Bad(e) => write!(f, "bad VCD: {e}"),
        }
    }
}

impl std::error::Error for VcdError {}

/// Reads the per-clock samples of window unit `unit` (traced as `uut$unit`) in a VCD.
pub fn read_vcd(reader: impl BufRead, unit: usize) -> Result<Vec<Sample>, VcdError> {
    let mut parser = vcd::Parser::new(reader);
    let header = parser.parse_header().map_err(VcdError::NotVcd)?;
    let scope_name = format!("uut${unit}");
    let top = header
        .items
        .iter()
        .find_map(|i| match i {
            ScopeItem::Scope(s) if s.identifier == scope_name => Some(s),
            _ => None,
        })
        .ok_or_else(|| VcdError::NoScope(scope_name.clone()))?;
    let mut ids: HashMap<IdCode, usize> = HashMap::new();
    let mut cur = Sample::default();
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
                .ok_or(VcdError::Lacks(name))?;
        }
        let leaf = path[path.len() - 1];
        let var = scope.find_var(leaf).ok_or(VcdError::Lacks(name))?;
        if *name == "port.set_xn.q" {
            cur.wide = var.size > 8;
        }
        ids.insert(var.code, k);
    }
    if let Some(v) = top.find_var("clock") {
        clock_id = Some(v.code);
    }
    let clock_id = clock_id.ok_or(VcdError::Lacks("clock"))?;
    let mut clock_high = false;
    let mut out = Vec::new();
    let mut started = false;
    let mut time = 0;
    for cmd in parser {
        let cmd = cmd.map_err(VcdError::Bad)?;
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
                    Some(13) => cur.pending.decimate = b,
                    _ => {}
                }
            }
            Command::ChangeVector(id, v) => {
                let n = v.iter().fold(0u32, |acc, b| (acc << 1) | u32::from(b == Value::V1));
                match ids.get(&id) {
                    Some(3) => cur.coord_data = n,
                    Some(9) => cur.pending.window.xmin = n,
                    Some(10) => cur.pending.window.xmax = n,
                    Some(11) => cur.pending.window.ymin = n,
                    Some(12) => cur.pending.window.ymax = n,
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

