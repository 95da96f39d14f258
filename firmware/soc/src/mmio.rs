//! The SoC's hardware (hdl/soc/coopwin_soc.v's memory map): the window unit's coordinate pins
//! as a register ([`CoordinatePins`], driven by the `ports` driver's four-phase handshake), the
//! capture DMA's pixel RAM, the cycle counter, the UART (`embedded_io::Write`) and a console.
use coopwin_firmware::ports::window::CoordinatePins;
use core::ptr::{read_volatile, write_volatile};

const UART: usize = 0x8000_0000;
const EXIT: usize = 0x8000_0004;
const CONSOLE: usize = 0x8000_0008;
const WIN: usize = 0x8000_1000;
/// The window pixel RAM: byte k of the last window at `PIXELS + k`.
pub const PIXELS: usize = 0x9000_0000;
/// Its size in bytes.
pub const PIXEL_BYTES: usize = 1 << 16;

/// Status bits (register 0x04).
pub mod status {
    /// CRDY1.
    pub const READY: u32 = 1 << 0;
    /// The last complete set was refused.
    pub const COORD_ERROR: u32 = 1 << 1;
    /// A window is armed or open.
    pub const ARMED: u32 = 1 << 2;
    /// A window is done (sticky).
    pub const DONE: u32 = 1 << 3;
    /// A set was refused (sticky).
    pub const REFUSED: u32 = 1 << 4;
    /// A set was accepted (sticky).
    pub const ACCEPTED: u32 = 1 << 5;
}

fn reg(offset: usize) -> u32 {
    // SAFETY: an I/O register of the SoC's map, uncached (bit 31), word aligned.
    unsafe { read_volatile((WIN + offset) as *const u32) }
}

fn set_reg(offset: usize, v: u32) {
    // SAFETY: as `reg`.
    unsafe { write_volatile((WIN + offset) as *mut u32, v) }
}

/// The window unit's status (bits in [`status`]).
pub fn status() -> u32 {
    reg(0x04)
}

/// Clears the sticky status bits in `bits`.
pub fn clear(bits: u32) {
    set_reg(0x04, bits);
}

/// Pixels the DMA wrote for the last window.
pub fn pixel_count() -> usize {
    reg(0x08) as usize
}

/// The frame (counted from 1 at the first `fval` since reset) the last window came from.
pub fn done_frame() -> u32 {
    reg(0x0C)
}

/// The cycle counter.
pub fn cycle() -> u32 {
    reg(0x10)
}

/// The cycle of the last window's done (the clock after its last pixel).
pub fn done_cycle() -> u32 {
    reg(0x14)
}

/// Frames the camera has started since reset (`fval` rising edges).
pub fn frames() -> u32 {
    reg(0x18)
}

/// Pixels the capture DMA has written since reset (its write port's busy clocks).
pub fn dma_cycles() -> u32 {
    reg(0x1C)
}

/// Clocks the instruction bus and the data bus were busy since reset.
pub fn bus_busy() -> (u32, u32) {
    (reg(0x20), reg(0x24))
}

/// Instructions retired since reset (the CPU's `minstret`, low word).
pub fn instret() -> u32 {
    let n: u32;
    // SAFETY: reads a counter CSR (VexRiscv's CsrPlugin with every CSR), no side effect.
    unsafe { core::arch::asm!("csrr {0}, minstret", out(reg) n, options(nomem, nostack)) };
    n
}

/// Lets the window unit's interrupt line (window done) wake the CPU from [`wait`]: VexRiscv's
/// external interrupt mask (CSR 0xBC0, LiteX's) and `mie.MEIE`. `mstatus.MIE` stays clear, so
/// the interrupt is never taken as a trap: `wfi` returns once it is pending, and the loop
/// reads the status.
pub fn enable_window_interrupt() {
    // SAFETY: CSR writes that only enable a wake-up source; no trap can follow (MIE is 0).
    unsafe {
        core::arch::asm!("csrw 0xBC0, {0}", "csrs mie, {1}", in(reg) 1u32, in(reg) 1u32 << 11, options(nomem, nostack));
    }
}

/// Sleeps until an enabled interrupt is pending (`wfi`).
pub fn wait() {
    // SAFETY: `wfi` only stalls the core.
    unsafe { core::arch::asm!("wfi", options(nomem, nostack)) };
}

/// The last window's pixels (the DMA's RAM, read as bytes through the uncached I/O region).
pub fn pixels(n: usize) -> &'static [u8] {
    // SAFETY: the pixel RAM is PIXEL_BYTES of readable I/O memory; the DMA writes it only
    // while a window is armed, and the firmware reads it only after the window is done and
    // before it writes the next set.
    unsafe { core::slice::from_raw_parts(PIXELS as *const u8, n.min(PIXEL_BYTES)) }
}

/// The coordinate port's pins as a register: CSTRB1, the byte and the decimation line
/// written, CRDY1 read.
pub struct Pins;

impl CoordinatePins for Pins {
    type Error = core::convert::Infallible;
    fn drive(&mut self, strobe: bool, data: u8, decimate: bool) -> Result<(), Self::Error> {
        set_reg(0x00, u32::from(strobe) | (u32::from(data) << 8) | (u32::from(decimate) << 16));
        Ok(())
    }
    fn ready(&mut self) -> Result<bool, Self::Error> {
        Ok(status() & status::READY != 0)
    }
}

/// A byte-wide output register: the UART (position updates) or the console (text).
pub struct Port(usize);

/// The UART: position updates in the link format.
pub const fn uart() -> Port {
    Port(UART)
}

/// The console: the firmware's measurements as text lines (the simulation logs them).
pub const fn console() -> Port {
    Port(CONSOLE)
}

impl embedded_io::ErrorType for Port {
    type Error = core::convert::Infallible;
}

impl embedded_io::Write for Port {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        for &b in buf {
            // SAFETY: the port's byte register (uncached I/O).
            unsafe { write_volatile(self.0 as *mut u32, u32::from(b)) }
        }
        Ok(buf.len())
    }
    fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

impl core::fmt::Write for Port {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let _ = embedded_io::Write::write(self, s.as_bytes());
        Ok(())
    }
}

/// Ends the simulation with `code` (0: success).
pub fn exit(code: u8) -> ! {
    // SAFETY: the exit register (uncached I/O).
    unsafe { write_volatile(EXIT as *mut u32, u32::from(code)) };
    loop {
        core::hint::spin_loop();
    }
}
