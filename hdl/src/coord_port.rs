//! The coordinate input section of the window logic (thesis 2.2.2, Fig. A1.1): the C40 writes
//! a window's coordinates one byte at a time over comm port 1 (CSTRB1/CRDY1) and the logic keeps
//! them in four registers (thesis XN, XX, YN, YX).
//!
//! Departures from the thesis (see `docs/window-logic.md`):
//! - the four-phase handshake is synchronous to the pixel clock, instead of clocking the
//!   coordinate registers with the C40's strobe (the thesis's AC clock), so the design has one
//!   clock domain;
//! - the bytes of an incomplete set are held apart (`in_*`), each coordinate pair checked as its
//!   second coordinate arrives, and the set judged on the clock after its last byte: a valid set
//!   replaces the pending one, an invalid set is refused and raises `coord_error`, leaving the
//!   pending set untouched;
//! - a sensor wider or taller than 256 takes two bytes a coordinate, high byte first, and a set
//!   must lie inside the sensor (xmax < width, ymax < height) as well as be ordered.
use crate::reg::Reg;
use rust_hdl::prelude::*;

/// Byte-wide coordinate port with the validity check of thesis 2.2.1 (xmin < xmax, ymin < ymax),
/// for a sensor of up to 2^C columns and rows.
#[derive(Clone, Debug, LogicBlock)]
pub struct CoordPort<const C: usize> {
    /// Pixel clock (thesis PVC); the handshake is sampled on its rising edge.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high: back to the power-on state.
    pub reset: Signal<In, Bit>,
    /// Thesis CSTRB1: the writer offers `coord_data`.
    pub coord_strobe: Signal<In, Bit>,
    /// Thesis port 1 D0-D7: the coordinate byte (xmin, xmax, ymin, ymax; high bytes first when
    /// coordinates take two bytes).
    pub coord_data: Signal<In, Bits<8>>,
    /// Thesis CRDY1: the byte has been taken; falls once the strobe is seen low.
    pub coord_ready: Signal<Out, Bit>,
    /// 25% resolution requested for the set being completed.
    pub decimate: Signal<In, Bit>,
    /// The last complete set was invalid and was refused.
    pub coord_error: Signal<Out, Bit>,
    /// A valid set is latched on this clock edge (the thesis's AC pulse that sets START).
    pub loaded: Signal<Out, Bit>,
    /// A valid set was latched on the last clock edge (`loaded` registered): one clock per set.
    pub set_accepted: Signal<Out, Bit>,
    /// Pending window, thesis XN (minimum column).
    pub xn: Signal<Out, Bits<C>>,
    /// Pending window, thesis XX (maximum column).
    pub xx: Signal<Out, Bits<C>>,
    /// Pending window, thesis YN (minimum row).
    pub yn: Signal<Out, Bits<C>>,
    /// Pending window, thesis YX (maximum row).
    pub yx: Signal<Out, Bits<C>>,
    /// Pending window is decimated (every other pixel of every other row).
    pub dec: Signal<Out, Bit>,
    /// Two bytes a coordinate (the sensor is wider or taller than 256).
    wide: Constant<Bit>,
    /// Index of a set's last byte (ymax, or its low byte): 3, or 7 when `wide`.
    last_byte: Constant<Bits<3>>,
    /// Index of the byte that completes xmax: 1, or 3 when `wide`.
    xmax_byte: Constant<Bits<3>>,
    /// The sensor's last column and row (width - 1, height - 1).
    xlast: Constant<Bits<16>>,
    ylast: Constant<Bits<16>>,
    /// CSTRB1, port 1 data and the decimation bit registered on arrival, so no path runs from
    /// the processor's pins into the set's register enables.
    strobe_r: Reg<Bit>,
    data_r: Reg<Bits<8>>,
    decimate_r: Reg<Bit>,
    /// Byte offered and not yet taken.
    take: Signal<Local, Bit>,
    ready: Reg<Bit>,
    /// Which byte of the set comes next.
    index: Reg<Bits<3>>,
    /// The thesis's shift registers, cut to the last three bytes taken: each byte enters at
    /// `sh7` and moves one on. When the byte completing xmax (or ymax) is in `data_r`, the
    /// coordinate pair is whole: `{sh5, sh6}` and `{sh7, data_r}` when `wide`, `sh7` and
    /// `data_r` otherwise. The pair is checked and kept then, so the check after the last byte
    /// is two flip-flops.
    sh5: Reg<Bits<8>>,
    sh6: Reg<Bits<8>>,
    sh7: Reg<Bits<8>>,
    /// The coordinate the byte taken now completes, and the one before it.
    this_value: Signal<Local, Bits<16>>,
    prev_value: Signal<Local, Bits<16>>,
    ordered: Signal<Local, Bit>,
    /// xmin < xmax < width, judged as xmax arrived.
    x_ok: Reg<Bit>,
    /// ymin < ymax < height, judged as ymax arrived.
    y_ok: Reg<Bit>,
    /// The set being written.
    in_xn: Reg<Bits<C>>,
    in_xx: Reg<Bits<C>>,
    in_yn: Reg<Bits<C>>,
    in_yx: Reg<Bits<C>>,
    /// Decimation sampled with the set's last byte.
    in_dec: Reg<Bit>,
    /// The set's last byte arrived on the last edge: judge the set on this one.
    check: Reg<Bit>,
    set_xn: Reg<Bits<C>>,
    set_xx: Reg<Bits<C>>,
    set_yn: Reg<Bits<C>>,
    set_yx: Reg<Bits<C>>,
    set_dec: Reg<Bit>,
    error: Reg<Bit>,
    /// `loaded` one clock later, for `set_accepted`.
    accepted: Reg<Bit>,
}

impl<const C: usize> CoordPort<C> {
    /// The port of a `width` x `height` sensor (each at most 2^C and 4096).
    pub fn new(width: usize, height: usize) -> Self {
        let last_byte = set_bytes(width, height) as u64 - 1;
        Self {
            clock: Default::default(),
            reset: Default::default(),
            coord_strobe: Default::default(),
            coord_data: Default::default(),
            coord_ready: Default::default(),
            decimate: Default::default(),
            coord_error: Default::default(),
            loaded: Default::default(),
            set_accepted: Default::default(),
            xn: Default::default(),
            xx: Default::default(),
            yn: Default::default(),
            yx: Default::default(),
            dec: Default::default(),
            wide: Constant::new(wide_coordinates(width, height)),
            last_byte: Constant::new(last_byte.into()),
            xmax_byte: Constant::new((last_byte / 2).into()),
            xlast: Constant::new((width as u64 - 1).into()),
            ylast: Constant::new((height as u64 - 1).into()),
            strobe_r: Default::default(),
            data_r: Default::default(),
            decimate_r: Default::default(),
            take: Default::default(),
            ready: Default::default(),
            index: Default::default(),
            sh5: Default::default(),
            sh6: Default::default(),
            sh7: Default::default(),
            this_value: Default::default(),
            prev_value: Default::default(),
            ordered: Default::default(),
            x_ok: Default::default(),
            y_ok: Default::default(),
            in_xn: Default::default(),
            in_xx: Default::default(),
            in_yn: Default::default(),
            in_yx: Default::default(),
            in_dec: Default::default(),
            check: Default::default(),
            set_xn: Default::default(),
            set_xx: Default::default(),
            set_yn: Default::default(),
            set_yx: Default::default(),
            set_dec: Default::default(),
            error: Default::default(),
            accepted: Default::default(),
        }
    }
}

/// The set-size rule (one byte a coordinate up to 256 columns and rows, two above), from the
/// firmware whose `CoordinateWriter` writes the sets: one rule for both sides of the port.
pub use coopwin_firmware::ports::window::{set_bytes, wide_coordinates};

impl<const C: usize> Logic for CoordPort<C> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, strobe_r, data_r, decimate_r, ready, index, sh5, sh6, sh7, x_ok, y_ok,
            in_xn, in_xx, in_yn, in_yx, in_dec, check, set_xn, set_xx, set_yn, set_yx, set_dec,
            error, accepted
        );
        self.coord_ready.next = self.ready.q.val();
        self.coord_error.next = self.error.q.val();
        self.xn.next = self.set_xn.q.val();
        self.xx.next = self.set_xx.q.val();
        self.yn.next = self.set_yn.q.val();
        self.yx.next = self.set_yx.q.val();
        self.dec.next = self.set_dec.q.val();
        self.set_accepted.next = self.accepted.q.val();

        // Four-phase handshake: take an offered byte, release CRDY1 once CSTRB1 falls.
        self.strobe_r.d.next = self.coord_strobe.val();
        self.data_r.d.next = self.coord_data.val();
        self.decimate_r.d.next = self.decimate.val();
        self.take.next = self.strobe_r.q.val() & !self.ready.q.val();
        self.this_value.next = bit_cast::<16, 8>(self.data_r.q.val());
        self.prev_value.next = bit_cast::<16, 8>(self.sh7.q.val());
        if self.wide.val() {
            self.this_value.next = (bit_cast::<16, 8>(self.sh7.q.val()) << 8) | bit_cast::<16, 8>(self.data_r.q.val());
            self.prev_value.next = (bit_cast::<16, 8>(self.sh5.q.val()) << 8) | bit_cast::<16, 8>(self.sh6.q.val());
        }
        self.ordered.next = self.prev_value.val() < self.this_value.val();
        self.check.d.next = self.take.val() & (self.index.q.val() == self.last_byte.val());
        if self.take.val() {
            self.ready.d.next = true;
            self.index.d.next = self.index.q.val() + 1;
            if self.index.q.val() == self.last_byte.val() {
                self.index.d.next = 0.into();
            }
            self.sh5.d.next = self.sh6.q.val();
            self.sh6.d.next = self.sh7.q.val();
            self.sh7.d.next = self.data_r.q.val();
            if self.index.q.val() == self.xmax_byte.val() {
                self.x_ok.d.next = self.ordered.val() & (self.this_value.val() <= self.xlast.val());
                self.in_xn.d.next = bit_cast::<C, 16>(self.prev_value.val());
                self.in_xx.d.next = bit_cast::<C, 16>(self.this_value.val());
            }
            if self.index.q.val() == self.last_byte.val() {
                self.y_ok.d.next = self.ordered.val() & (self.this_value.val() <= self.ylast.val());
                self.in_yn.d.next = bit_cast::<C, 16>(self.prev_value.val());
                self.in_yx.d.next = bit_cast::<C, 16>(self.this_value.val());
                self.in_dec.d.next = self.decimate_r.q.val();
            }
        }
        if !self.strobe_r.q.val() & self.ready.q.val() {
            self.ready.d.next = false;
        }

        // The set judged on the clock after its last byte.
        self.loaded.next = self.check.q.val() & self.x_ok.q.val() & self.y_ok.q.val();
        if self.loaded.val() {
            self.set_xn.d.next = self.in_xn.q.val();
            self.set_xx.d.next = self.in_xx.q.val();
            self.set_yn.d.next = self.in_yn.q.val();
            self.set_yx.d.next = self.in_yx.q.val();
            self.set_dec.d.next = self.in_dec.q.val();
        }
        if self.check.q.val() {
            self.error.d.next = !self.loaded.val();
        }
        self.accepted.d.next = self.loaded.val();

        if self.reset.val() {
            self.strobe_r.d.next = false;
            self.data_r.d.next = 0.into();
            self.decimate_r.d.next = false;
            self.ready.d.next = false;
            self.index.d.next = 0.into();
            self.check.d.next = false;
            self.sh5.d.next = 0.into();
            self.sh6.d.next = 0.into();
            self.sh7.d.next = 0.into();
            self.x_ok.d.next = false;
            self.y_ok.d.next = false;
            self.in_xn.d.next = 0.into();
            self.in_xx.d.next = 0.into();
            self.in_yn.d.next = 0.into();
            self.in_yx.d.next = 0.into();
            self.in_dec.d.next = false;
            self.set_xn.d.next = 0.into();
            self.set_xx.d.next = 0.into();
            self.set_yn.d.next = 0.into();
            self.set_yx.d.next = 0.into();
            self.set_dec.d.next = false;
            self.error.d.next = false;
            self.accepted.d.next = false;
        }
    }
}
