//! The coordinate input section of the window logic (thesis 2.2.2, Fig. A1.1): the C40 writes
//! a window's coordinates one byte at a time over comm port 1 (CSTRB1/CRDY1) and the logic keeps
//! them in four registers (thesis XN, XX, YN, YX).
//!
//! Departures from the thesis (see `docs/window-logic.md`):
//! - the four-phase handshake is synchronous to the pixel clock, instead of clocking the
//!   coordinate registers with the C40's strobe (the thesis's AC clock), so the design has one
//!   clock domain;
//! - the bytes of an incomplete set are held apart (`sh_*`) and the set is checked after its
//!   fourth byte arrives: a valid set replaces the pending one, an invalid set is refused and
//!   raises `coord_error`, leaving the pending set untouched.
use crate::reg::Reg;
use rust_hdl::prelude::*;

/// Byte-wide coordinate port with the validity check of thesis 2.2.1 (xmin < xmax, ymin < ymax).
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct CoordPort<const W: usize> {
    /// Pixel clock (thesis PVC); the handshake is sampled on its rising edge.
    pub clock: Signal<In, Clock>,
    /// Thesis CSTRB1: the writer offers `coord_data`.
    pub coord_strobe: Signal<In, Bit>,
    /// Thesis port 1 D0-D7: the coordinate byte, in the order xmin, xmax, ymin, ymax.
    pub coord_data: Signal<In, Bits<W>>,
    /// Thesis CRDY1: the byte has been taken; falls once the strobe is seen low.
    pub coord_ready: Signal<Out, Bit>,
    /// 25% resolution requested for the set being completed.
    pub decimate: Signal<In, Bit>,
    /// The last complete set was invalid and was refused.
    pub coord_error: Signal<Out, Bit>,
    /// A valid set is latched on this clock edge (the thesis's AC pulse that sets START).
    pub loaded: Signal<Out, Bit>,
    /// Pending window, thesis XN0-XN7 (minimum column).
    pub xn: Signal<Out, Bits<W>>,
    /// Pending window, thesis XX0-XX7 (maximum column).
    pub xx: Signal<Out, Bits<W>>,
    /// Pending window, thesis YN0-YN7 (minimum row).
    pub yn: Signal<Out, Bits<W>>,
    /// Pending window, thesis YX0-YX7 (maximum row).
    pub yx: Signal<Out, Bits<W>>,
    /// Pending window is decimated (every other pixel of every other row).
    pub dec: Signal<Out, Bit>,
    /// CSTRB1, port 1 data and the decimation bit registered on arrival, so no path runs from
    /// the processor's pins into the set's register enables.
    strobe_r: Reg<Bit>,
    data_r: Reg<Bits<W>>,
    decimate_r: Reg<Bit>,
    /// Byte offered and not yet taken.
    take: Signal<Local, Bit>,
    ready: Reg<Bit>,
    /// Which byte of the set comes next (0 = xmin ... 3 = ymax).
    index: Reg<Bits<2>>,
    /// The thesis's shift registers: each byte taken enters at `sh_yx` and moves one on, so
    /// after the fourth they hold xmin, xmax, ymin, ymax. One enable (`take`) for all.
    sh_xn: Reg<Bits<W>>,
    sh_xx: Reg<Bits<W>>,
    sh_yn: Reg<Bits<W>>,
    sh_yx: Reg<Bits<W>>,
    sh_dec: Reg<Bit>,
    /// Whether each byte exceeded the one before, shifted like the bytes: after the fourth,
    /// `lt0` is ymin < ymax and `lt2` is xmin < xmax.
    lt0: Reg<Bit>,
    lt1: Reg<Bit>,
    lt2: Reg<Bit>,
    /// The fourth byte arrived on the last edge: judge the set on this one.
    check: Reg<Bit>,
    set_xn: Reg<Bits<W>>,
    set_xx: Reg<Bits<W>>,
    set_yn: Reg<Bits<W>>,
    set_yx: Reg<Bits<W>>,
    set_dec: Reg<Bit>,
    error: Reg<Bit>,
}

impl<const W: usize> Logic for CoordPort<W> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, strobe_r, data_r, decimate_r, ready, index, sh_xn, sh_xx, sh_yn, sh_yx,
            sh_dec, lt0, lt1, lt2, check, set_xn, set_xx, set_yn, set_yx, set_dec, error
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
        self.check.d.next = false;
        if self.take.val() {
            self.ready.d.next = true;
            self.index.d.next = self.index.q.val() + 1;
            self.check.d.next = self.index.q.val() == 3;
            self.sh_xn.d.next = self.sh_xx.q.val();
            self.sh_xx.d.next = self.sh_yn.q.val();
            self.sh_yn.d.next = self.sh_yx.q.val();
            self.sh_yx.d.next = self.data_r.q.val();
            self.sh_dec.d.next = self.decimate_r.q.val();
            self.lt2.d.next = self.lt1.q.val();
            self.lt1.d.next = self.lt0.q.val();
            self.lt0.d.next = self.sh_yx.q.val() < self.data_r.q.val();
        }
        if !self.strobe_r.q.val() & self.ready.q.val() {
            self.ready.d.next = false;
        }

        self.loaded.next = self.check.q.val() & self.lt0.q.val() & self.lt2.q.val();
        if self.loaded.val() {
            self.set_xn.d.next = self.sh_xn.q.val();
            self.set_xx.d.next = self.sh_xx.q.val();
            self.set_yn.d.next = self.sh_yn.q.val();
            self.set_yx.d.next = self.sh_yx.q.val();
            self.set_dec.d.next = self.sh_dec.q.val();
        }
        if self.check.q.val() {
            self.error.d.next = !self.loaded.val();
        }
    }
}
