//! The tracking firmware on a Cortex-M4F (QEMU `mps2-an386`, or `netduinoplus2`'s STM32F405 with
//! the `stm32f405` feature; with `partner`, `peripheral` or `watch` too, that processor's own
//! image in 64 KiB of its SRAM, running its part of the suite: `suite::run_partner`,
//! `run_peripheral`, `run_watch`), thesis 2.6: the window processors' code on a real embedded
//! target. It prints the parity suite's lines
//! (`coopwin_parity::suite`: every kernel on the benchmark inputs, and the COOP Foveal pair on
//! the recorded window stream), which `scripts/board.sh` diffs against the host's
//! `fixtures/board/expected.txt`; then it drives the window unit's coordinate and pixel ports
//! through embedded-hal pins ([`pins`]). Lines starting with `#` are measurements, not
//! compared: instructions per kernel (SysTick under `-icount shift=0`) and the stack's
//! high-water mark (painted).
#![no_std]
#![no_main]

mod pins;

use core::fmt::{self, Write};
use cortex_m::peripheral::{syst::SystClkSource, SYST};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio};
use coopwin_parity::suite::{self, Meter};

/// Semihosting stdout, one host call per line (a call per `fmt` piece would be slow).
struct Out {
    buf: [u8; 256],
    len: usize,
}

impl Out {
    const fn new() -> Self {
        Out { buf: [0; 256], len: 0 }
    }
    fn flush(&mut self) {
        if let Ok(mut s) = hio::hstdout() {
            let _ = s.write_all(&self.buf[..self.len]);
        }
        self.len = 0;
    }
}

impl Write for Out {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for &b in s.as_bytes() {
            if self.len == self.buf.len() {
                self.flush();
            }
            self.buf[self.len] = b;
            self.len += 1;
            if b == b'\n' {
                self.flush();
            }
        }
        Ok(())
    }
}

/// SysTick, free-running from the core clock. With `-icount shift=0` an instruction takes
/// 1 ns of virtual time; QEMU's mps2 clocks SysTick at 25 MHz (40 instructions a tick), the
/// STM32F405 at its 168 MHz system clock (about 5.95). The ratio is measured at start
/// ([`calibrate`]) rather than assumed, as a fraction.
fn now() -> u32 {
    SYST::get_current()
}

fn elapsed(start: u32) -> u32 {
    // A 24-bit down-counter: wrap-safe for spans under 2^24 ticks (671 M instructions).
    start.wrapping_sub(now()) & 0x00FF_FFFF
}

/// `2 n` instructions exactly: a `subs`/`bne` loop.
#[inline(never)]
fn spin(n: u32) {
    // SAFETY: register-only loop, no memory or stack.
    unsafe {
        core::arch::asm!("1:", "subs {0}, {0}, #1", "bne 1b", inout(reg) n => _, options(nomem, nostack));
    }
}

/// Instructions per SysTick tick as a fraction `(instructions, ticks)`, from a loop of known
/// length. A ratio within 0.1 % of a whole number is that number (the mps2's 40: the loop's
/// entry and exit add a few instructions), so its counts are whole ticks times 40.
fn calibrate() -> (u32, u32) {
    let n = 1_000_000;
    let t = now();
    spin(n);
    let (i, t) = (2 * n, elapsed(t).max(1));
    let whole = (i + t / 2) / t;
    if whole > 0 && (whole * t).abs_diff(i) <= t / 1000 * whole {
        (whole, 1)
    } else {
        (i, t)
    }
}

/// Counts each kernel's instructions; pure kernels are run `REPS` more times so the count's
/// granularity (one tick) is divided by `REPS`.
struct Icount {
    /// Instructions and SysTick ticks of the calibration loop.
    per: (u32, u32),
    out: Out,
}

impl Icount {
    /// Instructions in `ticks` SysTick ticks over `reps` runs, rounded to the nearest.
    fn insns(&self, ticks: u32, reps: u32) -> u64 {
        let (i, t) = (u64::from(self.per.0), u64::from(self.per.1) * u64::from(reps));
        (u64::from(ticks) * i + t / 2) / t
    }
}

const REPS: u32 = 16;

impl Meter for Icount {
    fn kernel<R>(&mut self, id: &str, f: &mut dyn FnMut() -> R) -> R {
        let r = f();
        let t = now();
        for _ in 0..REPS {
            core::hint::black_box(f());
        }
        let insns = self.insns(elapsed(t), REPS);
        let _ = writeln!(self.out, "# icount {id} {insns} reps={REPS}");
        r
    }
    fn once<R>(&mut self, id: &str, f: &mut dyn FnMut() -> R) -> R {
        let t = now();
        let r = f();
        let insns = self.insns(elapsed(t), 1);
        let _ = writeln!(self.out, "# icount {id} {insns} reps=1");
        r
    }
}

const PAINT: u32 = 0xC0DE_C0DE;

extern "C" {
    static mut __sheap: u32;
    static _stack_start: u32;
}

/// Fills the free stack (from the end of .bss to just below the current frame) with
/// [`PAINT`]; returns the painted range.
fn paint_stack() -> (usize, usize) {
    let bottom = core::ptr::addr_of_mut!(__sheap) as usize;
    let sp = cortex_m::register::msp::read() as usize;
    let top = sp - 64;
    let mut p = bottom;
    while p < top {
        // SAFETY: words between the end of .bss/.uninit and below the live stack are unused.
        unsafe { core::ptr::write_volatile(p as *mut u32, PAINT) };
        p += 4;
    }
    (bottom, top)
}

/// Deepest stack use since painting: bytes from the stack's top to the lowest word written.
fn stack_used(bottom: usize) -> usize {
    let top = core::ptr::addr_of!(_stack_start) as usize;
    let mut p = bottom;
    // SAFETY: reads within RAM, below the live stack.
    while p < top && unsafe { core::ptr::read_volatile(p as *const u32) } == PAINT {
        p += 4;
    }
    top - p
}

#[entry]
fn main() -> ! {
    let (bottom, _) = paint_stack();
    let mut syst = match cortex_m::Peripherals::take() {
        Some(p) => p.SYST,
        None => fail("peripherals taken twice"),
    };
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(0x00FF_FFFF);
    syst.clear_current();
    syst.enable_counter();

    let mut out = Out::new();
    let per = calibrate();
    let mut meter = Icount { per, out: Out::new() };
    // An integer ratio (the mps2's 40) prints as it always has; the STM32's as a fraction.
    if per.1 == 1 {
        let _ = writeln!(meter.out, "# calibration instructions_per_tick={}", per.0);
    } else {
        let _ = writeln!(meter.out, "# calibration instructions_per_tick={}/{}", per.0, per.1);
    }
    if let Err(e) = run(&mut out, &mut meter) {
        let _ = writeln!(out, "error {e:?}");
        fail("suite");
    }
    match pins::exercise(&mut meter) {
        Ok(line) => {
            let _ = writeln!(out, "{line}");
        }
        Err(e) => {
            let _ = writeln!(out, "error pins {e:?}");
            fail("pins");
        }
    }
    #[cfg(not(any(feature = "partner", feature = "peripheral", feature = "watch", feature = "master")))]
    sizes(&mut out);
    let top = core::ptr::addr_of!(_stack_start) as usize;
    let _ = writeln!(out, "# stack used={} painted_from={bottom:#x} top={top:#x}", stack_used(bottom));
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi();
    }
}

#[cfg(any(
    all(feature = "partner", any(feature = "peripheral", feature = "watch", feature = "master")),
    all(feature = "peripheral", any(feature = "watch", feature = "master")),
    all(feature = "watch", feature = "master")
))]
compile_error!("one processor's image at a time: `partner`, `peripheral`, `watch` or `master`");

/// The suite this image runs: a processor's part of it (`partner`, `peripheral`, `watch`), or
/// all of it.
fn run(out: &mut Out, meter: &mut Icount) -> Result<(), suite::SuiteError> {
    #[cfg(feature = "partner")]
    return suite::run_partner(out, meter);
    #[cfg(feature = "peripheral")]
    return suite::run_peripheral(out, meter);
    #[cfg(feature = "watch")]
    return suite::run_watch(out, meter);
    #[cfg(feature = "master")]
    return suite::run_master(out, meter);
    #[cfg(not(any(feature = "partner", feature = "peripheral", feature = "watch", feature = "master")))]
    suite::run(out, meter)
}

/// What the replay holds on the stack: the pair, its processors and one of its answers.
#[cfg(not(any(feature = "partner", feature = "peripheral", feature = "watch", feature = "master")))]
fn sizes(out: &mut Out) {
    use coopwin_firmware::processors::adapt::Adaptive;
    use coopwin_firmware::processors::{CornerPartner, Foveal, Step};
    use core::mem::size_of;
    let _ = writeln!(
        out,
        "# size pair={} master={} adapt={} partner={} step={}",
        size_of::<suite::CoopPair>(),
        size_of::<Foveal<{ suite::MASTER_SIDE }, { suite::MASTER_LK }>>(),
        size_of::<Adaptive<{ suite::MASTER_LK }>>(),
        size_of::<CornerPartner<{ suite::PARTNER_SIDE }>>(),
        size_of::<Step>()
    );
}

fn fail(why: &str) -> ! {
    let mut out = Out::new();
    let _ = writeln!(out, "error {why}");
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    let mut out = Out::new();
    let _ = writeln!(out, "panic {info}");
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}
