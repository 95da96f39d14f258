//! The window logic of one windowing unit (thesis 2.2.2, Figs. 2.3, A1.1, A1.2, Appendix B):
//! camera sync signals drive X/Y position counters, equality comparators raise the XMIN/XMAX/
//! YMIN/YMAX flags, and the pixels inside the window are strobed to the processor (CSTRB4).
//!
//! Pipeline, all on the rising edge of `clock`:
//! - edge k: the camera's `fval`, `lval`, `pixel` are registered (thesis FVC, LVC and the first
//!   octal data flip-flop); `xcount` becomes the column of that registered pixel; frame and
//!   line transitions (FVLH, FVHL, LVHL) are seen one clock later, from flip-flops;
//! - edge k+1: the window test runs on the registered pixel and `pixel_strobe`/`pixel_out` are
//!   registered (the second data flip-flop), so a pixel leaves one clock after it was sampled.
//!
//! Departures from the thesis are listed in `docs/window-logic.md`: rows count from 0 (the
//! thesis's Y count 1..256), coordinates are double-buffered (`CoordPort` holds the pending
//! set, `xn..yx` here the active one, swapped at FVAL rising), a decimation bit gives the 25%
//! window, and the counter width `W` is a parameter.
use crate::coord_port::CoordPort;
use rust_hdl::prelude::*;

/// One window unit: `W`-bit position counters and coordinates (8 for the 256x256 CA-D1).
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct WindowUnit<const W: usize> {
    /// Pixel clock (thesis STROBE, inverted into PVC).
    pub clock: Signal<In, Clock>,
    /// Frame valid (thesis FVAL).
    pub fval: Signal<In, Bit>,
    /// Line valid (thesis LVAL).
    pub lval: Signal<In, Bit>,
    /// Camera data (thesis OD0-OD7), one pixel per clock while `fval & lval`.
    pub pixel: Signal<In, Bits<8>>,
    /// Coordinate byte offered (thesis CSTRB1).
    pub coord_strobe: Signal<In, Bit>,
    /// Coordinate byte, xmin, xmax, ymin, ymax in turn (thesis port 1 D0-D7).
    pub coord_data: Signal<In, Bits<W>>,
    /// Coordinate byte taken (thesis CRDY1).
    pub coord_ready: Signal<Out, Bit>,
    /// 25% resolution for the window of the set being completed.
    pub decimate: Signal<In, Bit>,
    /// High for exactly one clock per delivered pixel (thesis CSTRB4, active high here).
    pub pixel_strobe: Signal<Out, Bit>,
    /// The delivered pixel, valid while `pixel_strobe` (thesis port 4 D0-D7).
    pub pixel_out: Signal<Out, Bits<8>>,
    /// The last complete coordinate set was invalid and was refused.
    pub coord_error: Signal<Out, Bit>,
    port: CoordPort<W>,
    /// Thesis FVC: frame valid synchronised to the pixel clock.
    fvc: DFF<Bit>,
    /// Thesis LVC: line valid synchronised to the pixel clock.
    lvc: DFF<Bit>,
    /// First data delay stage: the pixel sampled with `lvc`.
    pxc: DFF<Bits<8>>,
    /// FVC one clock later, to find its transitions from flip-flops alone.
    fvd: DFF<Bit>,
    /// LVC one clock later.
    lvd: DFF<Bit>,
    /// Thesis FVLH: frame valid low-to-high transition (a frame starts).
    fvlh: Signal<Local, Bit>,
    /// Thesis FVHL: frame valid high-to-low transition (a frame ends).
    fvhl: Signal<Local, Bit>,
    /// Thesis LVHL: line valid high-to-low transition inside a frame (a line ends).
    lvhl: Signal<Local, Bit>,
    /// Thesis X0-X7: column of the pixel in `pxc`.
    xcount: DFF<Bits<W>>,
    /// Thesis Y0-Y7: row of the current line (0-based; the thesis counts 1..256).
    ycount: DFF<Bits<W>>,
    /// Thesis START: a valid set is pending for a coming frame.
    start: DFF<Bit>,
    /// Thesis WLEN: window logic enabled, a set pending while between frames (START & NFV).
    wlen: Signal<Local, Bit>,
    /// A pending set becomes the active window at this frame start (registered as FVAL rises,
    /// so its fan-out to the active registers starts at a flip-flop).
    arm: DFF<Bit>,
    /// Thesis STRBEN: strobes enabled for the frame in progress.
    strben: DFF<Bit>,
    /// Thesis WLRST: the window logic is reset (end of frame, or last window line done).
    wlrst: Signal<Local, Bit>,
    /// Active window, thesis XN0-XN7 (minimum column), loaded from the pending set at FVLH.
    xn: DFF<Bits<W>>,
    /// Active window, thesis XX0-XX7 (maximum column).
    xx: DFF<Bits<W>>,
    /// Active window, thesis YN0-YN7 (minimum row).
    yn: DFF<Bits<W>>,
    /// Active window, thesis YX0-YX7 (maximum row).
    yx: DFF<Bits<W>>,
    /// Active window is decimated.
    dec: DFF<Bit>,
    /// Thesis XMIN: the X count equals xmin.
    xmin: Signal<Local, Bit>,
    /// Thesis XMAX: the X count equals xmax.
    xmax: Signal<Local, Bit>,
    /// Thesis YMIN flag: the Y count equals ymin (registered, as the Y count holds a line long).
    ymin: DFF<Bit>,
    /// Thesis YMAX flag: the Y count equals ymax (registered).
    ymax: DFF<Bit>,
    /// Columns from xmin on have been reached in this line, xmax not yet passed.
    xrun: DFF<Bit>,
    /// Thesis YVAL flip-flop: rows from ymin on reached in this frame, ymax not yet passed.
    yval: DFF<Bit>,
    /// Thesis XYVAL: the pixel in `pxc` lies in the window (before decimation).
    xyval: Signal<Local, Bit>,
    /// The pixel in `pxc` is on the 25% grid anchored at (xmin, ymin), or decimation is off.
    decok: Signal<Local, Bit>,
    /// Second data delay stage and CSTRB4.
    strobe: DFF<Bit>,
    data: DFF<Bits<8>>,
}

impl<const W: usize> Logic for WindowUnit<W> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, fvc, lvc, pxc, fvd, lvd, xcount, ycount, start, strben, xn, xx, yn, yx, dec,
            arm, ymin, ymax, xrun, yval, strobe, data
        );
        self.port.clock.next = self.clock.val();
        self.port.coord_strobe.next = self.coord_strobe.val();
        self.port.coord_data.next = self.coord_data.val();
        self.port.decimate.next = self.decimate.val();
        self.coord_ready.next = self.port.coord_ready.val();
        self.coord_error.next = self.port.coord_error.val();
        self.pixel_strobe.next = self.strobe.q.val();
        self.pixel_out.next = self.data.q.val();

        // Synchronise the camera (FVC, LVC, data delay) and find its transitions one clock on,
        // as the thesis's transition flags are (B1.2 step 9).
        self.fvc.d.next = self.fval.val();
        self.lvc.d.next = self.lval.val();
        self.pxc.d.next = self.pixel.val();
        self.fvd.d.next = self.fvc.q.val();
        self.lvd.d.next = self.lvc.q.val();
        self.fvlh.next = self.fvc.q.val() & !self.fvd.q.val();
        self.fvhl.next = !self.fvc.q.val() & self.fvd.q.val();
        self.lvhl.next = !self.lvc.q.val() & self.lvd.q.val() & self.fvc.q.val();

        // Position counters.
        self.xcount.d.next = 0.into();
        if self.lvc.q.val() {
            self.xcount.d.next = self.xcount.q.val() + 1;
        }
        if self.lvhl.val() {
            self.ycount.d.next = self.ycount.q.val() + 1;
        }

        // Magnitude (equality) comparators and the window test on the pixel in `pxc`.
        self.xmin.next = self.xcount.q.val() == self.xn.q.val();
        self.xmax.next = self.xcount.q.val() == self.xx.q.val();
        self.ymin.d.next = self.ycount.q.val() == self.yn.q.val();
        self.ymax.d.next = self.ycount.q.val() == self.yx.q.val();
        self.xyval.next = self.strben.q.val()
            & self.lvc.q.val()
            & (self.xrun.q.val() | self.xmin.val())
            & (self.yval.q.val() | self.ymin.q.val());
        self.decok.next = !self.dec.q.val()
            | ((self.xcount.q.val().get_bit(0) == self.xn.q.val().get_bit(0))
                & (self.ycount.q.val().get_bit(0) == self.yn.q.val().get_bit(0)));
        self.xrun.d.next =
            self.lvc.q.val() & (self.xrun.q.val() | self.xmin.val()) & !self.xmax.val();
        if self.lvhl.val() {
            self.yval.d.next = (self.yval.q.val() | self.ymin.q.val()) & !self.ymax.q.val();
        }
        self.strobe.d.next = self.xyval.val() & self.decok.val();
        self.data.d.next = self.pxc.q.val();

        // START -> WLEN -> STRBEN -> WLRST (Appendix B), the active set swapped in at FVLH.
        self.wlen.next = self.start.q.val() & !self.fvc.q.val();
        self.arm.d.next = self.fval.val() & self.wlen.val();
        self.wlrst.next = self.fvhl.val() | (self.lvhl.val() & self.ymax.q.val() & self.yval.q.val());
        self.start.d.next = self.port.loaded.val() | (self.start.q.val() & !self.arm.q.val());
        self.strben.d.next = self.arm.q.val() | (self.strben.q.val() & !self.wlrst.val());
        if self.arm.q.val() {
            self.xn.d.next = self.port.xn.val();
            self.xx.d.next = self.port.xx.val();
            self.yn.d.next = self.port.yn.val();
            self.yx.d.next = self.port.yx.val();
            self.dec.d.next = self.port.dec.val();
        }
        if self.fvlh.val() {
            self.ycount.d.next = 0.into();
            self.yval.d.next = false;
        }
    }
}
