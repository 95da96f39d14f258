//! The SoC's firmware image (riscv32imac): locks on to the target in the first window, then
//! tracks it with the Foveal processor, one window a step, each window's coordinates written
//! through the `ports` driver's handshake on the unit's MMIO pins, its pixels read from the
//! capture DMA's RAM (the core sleeping in `wfi` until the unit's window-done interrupt),
//! each position sent on the UART in the link format. Measurements go to
//! the console as `window ...` lines; once, a hostile coordinate set is written and must be
//! refused. Exit code 0 once the camera's last frame (`COOPWIN_SOC_FRAMES`) has started.
#![no_std]
#![no_main]

use core::fmt::Write as _;
use coopwin_firmware::kernels::view::WindowView;
use coopwin_firmware::ports::position::{FramedPositionSink, PositionSink};
use coopwin_firmware::ports::window::{bound_bytes, CoordinateWriter, WriteError};
use coopwin_firmware::types::{Decimation, Point, WindowRequest};
use coopwin_soc::mmio::{self, status, Pins};
use coopwin_soc::Tracker;

core::arch::global_asm!(
    ".section .text.start",
    ".globl _start",
    "_start:",
    "la sp, _stack_top",
    "la t0, _sbss",
    "la t1, _ebss",
    "1: bgeu t0, t1, 2f",
    "sw zero, 0(t0)",
    "addi t0, t0, 4",
    "j 1b",
    "2: call soc_main",
    "3: j 3b",
);

/// The frames the camera shows (the scene's first frames): no set is written once the last
/// has started.
const FRAMES: u32 = parse(env!("COOPWIN_SOC_FRAMES"));
/// The target on the first frame, X,Y in whole pixels (the scene's ground truth, rounded).
const TARGET: (u32, u32) = pair(env!("COOPWIN_SOC_TARGET"));
/// The windows after which the hostile sets are written: right after the lock-on, so every run
/// (the audit's short one too) has them and tracks on after them.
const HOSTILE_AFTER: u32 = 1;

const fn parse(s: &str) -> u32 {
    let b = s.as_bytes();
    let (mut i, mut v) = (0, 0);
    while i < b.len() {
        assert!(b[i].is_ascii_digit(), "a whole number");
        v = v * 10 + (b[i] - b'0') as u32;
        i += 1;
    }
    v
}

const fn pair(s: &str) -> (u32, u32) {
    let b = s.as_bytes();
    let (mut i, mut x, mut y, mut second) = (0, 0, 0, false);
    while i < b.len() {
        if b[i] == b',' {
            second = true;
        } else {
            assert!(b[i].is_ascii_digit(), "X,Y in whole pixels");
            let d = (b[i] - b'0') as u32;
            if second {
                y = y * 10 + d;
            } else {
                x = x * 10 + d;
            }
        }
        i += 1;
    }
    (x, y)
}

/// Writes one set's bytes through the driver's handshake and waits for the unit's verdict:
/// whether it accepted the set, and the clocks from queueing it to the verdict. Logs the set as queued (`set cycle=C bytes=.. dec=..`: the
/// processor's side of `coopwin audit`'s requests).
fn write_set(writer: &mut CoordinateWriter, pins: &mut Pins, con: &mut mmio::Port, bytes: &[u8], decimate: bool) -> Result<(bool, u32), WriteError> {
    mmio::clear(status::ACCEPTED | status::REFUSED | status::DONE);
    let _ = write!(con, "set cycle={}", mmio::cycle());
    for (k, b) in bytes.iter().enumerate() {
        let _ = write!(con, "{}{b}", if k == 0 { " bytes=" } else { "," });
    }
    let _ = writeln!(con, " dec={}", u8::from(decimate));
    let queued = mmio::cycle();
    writer.write_bytes(bytes, decimate)?;
    while writer.busy() {
        let Ok(()) = writer.poll(pins);
    }
    loop {
        let s = mmio::status();
        if s & (status::ACCEPTED | status::REFUSED) != 0 {
            return Ok((s & status::ACCEPTED != 0, mmio::cycle().wrapping_sub(queued)));
        }
    }
}

/// The hostile cases: a window over the frame's edge (the driver refuses it before the bus)
/// and a set with xmin > xmax written to the unit as raw bytes (the unit refuses it).
fn hostile(writer: &mut CoordinateWriter, pins: &mut Pins, con: &mut mmio::Port) -> bool {
    let over = WindowRequest { x0: 250, y0: 10, width: 24, height: 24, decimation: Decimation::Full };
    let driver = writer.write(&over) == Err(WriteError::OutOfRange);
    let unit = match bound_bytes([200, 100, 10, 20], false) {
        Ok(set) => matches!(write_set(writer, pins, con, &set, false), Ok((false, _))) && mmio::status() & status::COORD_ERROR != 0,
        Err(_) => false,
    };
    let _ = writeln!(con, "hostile over_edge_refused_by_driver={driver} reversed_refused_by_unit={unit}");
    driver && unit
}

#[no_mangle]
extern "C" fn soc_main() -> ! {
    let mut con = mmio::console();
    let mut pins = Pins;
    let mut writer = CoordinateWriter::new();
    let mut sink = FramedPositionSink::new(mmio::uart());
    let target = Point { x: TARGET.0 as f32, y: TARGET.1 as f32 };
    let mut tracker = Tracker::new(target);
    let mut req = tracker.lock_on_window();
    mmio::enable_window_interrupt();
    let _ = writeln!(con, "start target={},{} frames={FRAMES}", TARGET.0, TARGET.1);
    let mut windows = 0u32;
    let mut last_done: Option<u32> = None;
    loop {
        // The last frame has started: a set written now would wait for a frame that never comes.
        if mmio::frames() >= FRAMES {
            let _ = writeln!(con, "end windows={windows}");
            mmio::exit(0);
        }
        let bytes = match coopwin_firmware::ports::window::coordinate_set(&req, (256, 256)) {
            Ok(b) => b,
            Err(e) => fail(&mut con, "the driver refused the tracker's window", e),
        };
        let set_cycles = match write_set(&mut writer, &mut pins, &mut con, &bytes, req.decimation == Decimation::Quarter) {
            Ok((true, cycles)) => cycles,
            Ok((false, _)) => fail(&mut con, "the unit refused the tracker's window", ()),
            Err(e) => fail(&mut con, "the coordinate queue", e),
        };
        // The window-done interrupt wakes the core: one wake a window.
        let mut wakes = 0u32;
        while mmio::status() & status::DONE == 0 {
            mmio::wait();
            wakes += 1;
        }
        let (done, frame) = (mmio::done_cycle(), mmio::done_frame().saturating_sub(1));
        let (insn0, bus0) = (mmio::instret(), mmio::bus_busy());
        let (w, h) = req.delivered_size();
        let n = mmio::pixel_count();
        if n != w * h || req.decimation != Decimation::Full {
            let _ = writeln!(con, "error window pixels={n} expected={}", w * h);
            mmio::exit(5);
        }
        let view = match WindowView::new(mmio::pixels(n), w, h, w, u32::from(req.x0), u32::from(req.y0)) {
            Ok(v) => v,
            Err(e) => fail(&mut con, "window view", e),
        };
        let (update, next) = match tracker.on_window(&view, frame) {
            Ok(r) => r,
            Err(e) => fail(&mut con, "lock-on", e),
        };
        let computed = mmio::cycle();
        let (insn1, bus1) = (mmio::instret(), mmio::bus_busy());
        if let Some(u) = update {
            if let Err(e) = sink.emit(&u) {
                fail(&mut con, "position update", e);
            }
        }
        let sent = mmio::cycle();
        let _ = writeln!(
            con,
            "window n={windows} frame={frame} x0={} y0={} pixels={n} wakes={wakes} set_cycles={} done={done} compute_cycles={} compute_insns={} ibus_busy={} dbus_busy={} latency_cycles={} since_last_done={} dma_total={}",
            req.x0,
            req.y0,
            set_cycles,
            computed.wrapping_sub(done),
            insn1.wrapping_sub(insn0),
            bus1.0.wrapping_sub(bus0.0),
            bus1.1.wrapping_sub(bus0.1),
            sent.wrapping_sub(done),
            last_done.map_or(0, |l| done.wrapping_sub(l)),
            mmio::dma_cycles()
        );
        last_done = Some(done);
        windows += 1;
        if windows == HOSTILE_AFTER && !hostile(&mut writer, &mut pins, &mut con) {
            mmio::exit(6);
        }
        req = match next {
            Some(r) => r,
            None => {
                let _ = writeln!(con, "lost frame={frame}");
                mmio::exit(7);
            }
        };
    }
}

fn fail<E: core::fmt::Debug>(con: &mut mmio::Port, what: &str, e: E) -> ! {
    let _ = writeln!(con, "error {what}: {e:?}");
    mmio::exit(3)
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    let mut con = mmio::console();
    let _ = writeln!(con, "panic {info}");
    mmio::exit(101)
}
