//! The coordinate input section of the window logic (thesis 2.2.2, Fig. A1.1): the C40 writes
//! a window's coordinates one byte at a time over comm port 1 (CSTRB1/CRDY1) and the logic keeps
//! them in four registers (thesis XN, XX, YN, YX).
//!
//! Departures from the thesis (see `docs/window-logic.md`):
//! - the four-phase handshake is synchronous to the pixel clock, instead of clocking the
//!   coordinate registers with the C40's strobe (the thesis's AC clock), so the design has one
//!   clock domain;
//! - the bytes of an incomplete set are held apart (`sh0..sh7`) and the set is checked after its
//!   last byte arrives: a valid set replaces the pending one, an invalid set is refused and
//!   raises `coord_error`, leaving the pending set untouched;
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
    /// Index of a set's last byte: 3, or 7 when `wide`.
    last_byte: Constant<Bits<3>>,
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
    /// The thesis's shift registers: each byte taken enters at `sh7` and moves one on, so after
    /// a set's last byte `sh4..sh7` hold xmin, xmax, ymin, ymax (`sh0..sh7` their high and low
    /// bytes when `wide`). One enable (`take`) for all.
    sh0: Reg<Bits<8>>,
    sh1: Reg<Bits<8>>,
    sh2: Reg<Bits<8>>,
    sh3: Reg<Bits<8>>,
    sh4: Reg<Bits<8>>,
    sh5: Reg<Bits<8>>,
    sh6: Reg<Bits<8>>,
    sh7: Reg<Bits<8>>,
    sh_dec: Reg<Bit>,
    /// The set's coordinates as shifted in.
    in_xmin: Signal<Local, Bits<16>>,
    in_xmax: Signal<Local, Bits<16>>,
    in_ymin: Signal<Local, Bits<16>>,
    in_ymax: Signal<Local, Bits<16>>,
    /// The set's last byte arrived on the last edge: judge the set on this one.
    check: Reg<Bit>,
    set_xn: Reg<Bits<C>>,
    set_xx: Reg<Bits<C>>,
    set_yn: Reg<Bits<C>>,
    set_yx: Reg<Bits<C>>,
    set_dec: Reg<Bit>,
    error: Reg<Bit>,
}

impl<const C: usize> CoordPort<C> {
    /// The port of a `width` x `height` sensor (each at most 2^C and 4096).
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            clock: Default::default(),
            reset: Default::default(),
            coord_strobe: Default::default(),
            coord_data: Default::default(),
            coord_ready: Default::default(),
            decimate: Default::default(),
            coord_error: Default::default(),
            loaded: Default::default(),
            xn: Default::default(),
            xx: Default::default(),
            yn: Default::default(),
            yx: Default::default(),
            dec: Default::default(),
            wide: Constant::new(wide_coordinates(width, height)),
            last_byte: Constant::new(if wide_coordinates(width, height) { 7 } else { 3 }.into()),
            xlast: Constant::new((width as u64 - 1).into()),
            ylast: Constant::new((height as u64 - 1).into()),
            strobe_r: Default::default(),
            data_r: Default::default(),
            decimate_r: Default::default(),
            take: Default::default(),
            ready: Default::default(),
            index: Default::default(),
            sh0: Default::default(),
            sh1: Default::default(),
            sh2: Default::default(),
            sh3: Default::default(),
            sh4: Default::default(),
            sh5: Default::default(),
            sh6: Default::default(),
            sh7: Default::default(),
            sh_dec: Default::default(),
            in_xmin: Default::default(),
            in_xmax: Default::default(),
            in_ymin: Default::default(),
            in_ymax: Default::default(),
            check: Default::default(),
            set_xn: Default::default(),
            set_xx: Default::default(),
            set_yn: Default::default(),
            set_yx: Default::default(),
            set_dec: Default::default(),
            error: Default::default(),
        }
    }
}

/// True when a `width` x `height` sensor's coordinates take two bytes each.
pub fn wide_coordinates(width: usize, height: usize) -> bool {
    width.max(height) > 256
}

impl<const C: usize> Logic for CoordPort<C> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, strobe_r, data_r, decimate_r, ready, index, sh0, sh1, sh2, sh3, sh4, sh5,
            sh6, sh7, sh_dec, check, set_xn, set_xx, set_yn, set_yx, set_dec, error
        );
        self.coord_ready.next = self.ready.q.val();
        self.coord_error.next = self.error.q.val();
        self.xn.next = self.set_xn.q.val();
        self.xx.next = self.set_xx.q.val();
        self.yn.next = self.set_yn.q.val();
        self.yx.next = self.set_yx.q.val();
        self.dec.next = self.set_dec.q.val();

        // Four-phase handshake: take an offered byte, release CRDY1 once CSTRB1 falls.
        self.strobe_r.d.next = self.coord_strobe.val();
        self.data_r.d.next = self.coord_data.val();
        self.decimate_r.d.next = self.decimate.val();
        self.take.next = self.strobe_r.q.val() & !self.ready.q.val();
        self.check.d.next = self.take.val() & (self.index.q.val() == self.last_byte.val());
        if self.take.val() {
            self.ready.d.next = true;
            self.index.d.next = self.index.q.val() + 1;
            if self.index.q.val() == self.last_byte.val() {
                self.index.d.next = 0.into();
            }
            self.sh0.d.next = self.sh1.q.val();
            self.sh1.d.next = self.sh2.q.val();
            self.sh2.d.next = self.sh3.q.val();
            self.sh3.d.next = self.sh4.q.val();
            self.sh4.d.next = self.sh5.q.val();
            self.sh5.d.next = self.sh6.q.val();
            self.sh6.d.next = self.sh7.q.val();
            self.sh7.d.next = self.data_r.q.val();
            self.sh_dec.d.next = self.decimate_r.q.val();
        }
        if !self.strobe_r.q.val() & self.ready.q.val() {
            self.ready.d.next = false;
        }

        // The set as shifted in, and its check: ordered, and inside the sensor.
        self.in_xmin.next = bit_cast::<16, 8>(self.sh4.q.val());
        self.in_xmax.next = bit_cast::<16, 8>(self.sh5.q.val());
        self.in_ymin.next = bit_cast::<16, 8>(self.sh6.q.val());
        self.in_ymax.next = bit_cast::<16, 8>(self.sh7.q.val());
        if self.wide.val() {
            self.in_xmin.next = (bit_cast::<16, 8>(self.sh0.q.val()) << 8) | bit_cast::<16, 8>(self.sh1.q.val());
            self.in_xmax.next = (bit_cast::<16, 8>(self.sh2.q.val()) << 8) | bit_cast::<16, 8>(self.sh3.q.val());
            self.in_ymin.next = (bit_cast::<16, 8>(self.sh4.q.val()) << 8) | bit_cast::<16, 8>(self.sh5.q.val());
            self.in_ymax.next = (bit_cast::<16, 8>(self.sh6.q.val()) << 8) | bit_cast::<16, 8>(self.sh7.q.val());
        }
        self.loaded.next = self.check.q.val()
            & (self.in_xmin.val() < self.in_xmax.val())
            & (self.in_xmax.val() <= self.xlast.val())
            & (self.in_ymin.val() < self.in_ymax.val())
            & (self.in_ymax.val() <= self.ylast.val());
        if self.loaded.val() {
            self.set_xn.d.next = bit_cast::<C, 16>(self.in_xmin.val());
            self.set_xx.d.next = bit_cast::<C, 16>(self.in_xmax.val());
            self.set_yn.d.next = bit_cast::<C, 16>(self.in_ymin.val());
            self.set_yx.d.next = bit_cast::<C, 16>(self.in_ymax.val());
            self.set_dec.d.next = self.sh_dec.q.val();
        }
        if self.check.q.val() {
            self.error.d.next = !self.loaded.val();
        }

        if self.reset.val() {
            self.strobe_r.d.next = false;
            self.data_r.d.next = 0.into();
            self.decimate_r.d.next = false;
            self.ready.d.next = false;
            self.index.d.next = 0.into();
            self.check.d.next = false;
            self.sh0.d.next = 0.into();
            self.sh1.d.next = 0.into();
            self.sh2.d.next = 0.into();
            self.sh3.d.next = 0.into();
            self.sh4.d.next = 0.into();
            self.sh5.d.next = 0.into();
            self.sh6.d.next = 0.into();
            self.sh7.d.next = 0.into();
            self.sh_dec.d.next = false;
            self.set_xn.d.next = 0.into();
            self.set_xx.d.next = 0.into();
            self.set_yn.d.next = 0.into();
            self.set_yx.d.next = 0.into();
            self.set_dec.d.next = false;
            self.error.d.next = false;
        }
    }
}
