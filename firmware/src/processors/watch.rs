//! The Watch processor (thesis 2.3.1, 2.4): image differencing over the whole frame or one of
//! MPDF's strips, reporting the motion area and capturing the template at the first motion.
//! A whole-frame Watch can be split into strips, each its own processor ([`strip`]), whose
//! motion areas merge ([`merge`]) into exactly the whole frame's.
use super::messages::{Dest, Msg};
use super::params::Params;
use super::step::{Step, Work};
use super::template::Template;
use crate::kernels::motion::{detect_motion, MotionArea};
use crate::kernels::view::WindowView;
use crate::types::{Point, WindowRequest};


/// A Watch processor: differences consecutive acquisitions of its region (the whole frame,
/// or one of MPDF's strips) and reports the motion area. Without a template yet, it captures
/// one at the centre of the first motion it sees and sends it to the others.
pub struct Watch<'b> {
    region: WindowRequest,
    prev: &'b mut [u8],
    have_prev: bool,
    template_sent: bool,
    params: Params,
}

impl<'b> Watch<'b> {
    /// A Watch processor over `region`; `prev` stores the last acquisition (at least the
    /// region's pixel count). `template_known`: the template was given, don't capture one.
    pub fn new(region: WindowRequest, prev: &'b mut [u8], params: Params, template_known: bool) -> Self {
        Watch { region, prev, have_prev: false, template_sent: template_known, params }
    }

    /// The first request.
    pub fn start(&self) -> Step {
        let mut step = Step::new(Work::None);
        step.ask(Some(self.region));
        step
    }

    /// A Watch window arrived.
    pub fn on_window(&mut self, win: &WindowView<'_>) -> Step {
        let pixels = (win.width() * win.height()) as u32;
        let mut step = Step::new(Work::Motion { pixels });
        step.ask(Some(self.region));
        let Some(prev_buf) = self.prev.get(..pixels as usize) else { return step };
        if self.have_prev {
            let (ox, oy) = win.origin();
            let prev = WindowView::new(prev_buf, win.width(), win.height(), win.width(), ox, oy);
            if let Ok(prev) = prev {
                if let Ok(Some(area)) = detect_motion(&prev, win, self.params.motion_threshold) {
                    if area.count >= self.params.motion_min_pixels {
                        self.report(&mut step, win, area);
                    }
                }
            }
        }
        if win.pack_into(self.prev).is_some() {
            self.have_prev = true;
        }
        step
    }

    fn report(&mut self, step: &mut Step, win: &WindowView<'_>, a: MotionArea) {
        let c = Point { x: (a.xmin + a.xmax) as f32 / 2.0, y: (a.ymin + a.ymax) as f32 / 2.0 };
        if !self.template_sent {
            if let Some(t) = Template::capture(win, c, self.params.template as usize) {
                self.template_sent = true;
                step.send(Dest::Peripheral, Msg::Template(t.clone())).send(Dest::Foveal, Msg::Template(t));
            }
        }
        step.send(
            Dest::Peripheral,
            Msg::Motion { xmin: a.xmin as u16, xmax: a.xmax as u16, ymin: a.ymin as u16, ymax: a.ymax as u16 },
        );
    }
}

/// The `k`-th of `n` horizontal strips of `region` (2.3.3: MPDF's Watch windows, one a
/// processor): rows split as evenly as they go, the first strips one row taller; `None` for
/// `k >= n`. Together they cover `region`'s rows once each, so their areas [`merge`] into the
/// region's.
pub fn strip(region: WindowRequest, k: u16, n: u16) -> Option<WindowRequest> {
    if k >= n {
        return None;
    }
    let (rows, extra) = (region.height / n, region.height % n);
    let y0 = region.y0 + k * rows + k.min(extra);
    Some(WindowRequest { y0, height: rows + u16::from(k < extra), ..region })
}

/// The motion area of two disjoint sets of rows (or columns) from each one's: the union of
/// the boxes and the sum of the counts (saturating, as [`detect_motion`] counts). Merged over
/// strips that partition a region it equals [`detect_motion`] over the whole region.
pub fn merge(a: Option<MotionArea>, b: Option<MotionArea>) -> Option<MotionArea> {
    match (a, b) {
        (Some(a), Some(b)) => Some(MotionArea {
            xmin: a.xmin.min(b.xmin),
            xmax: a.xmax.max(b.xmax),
            ymin: a.ymin.min(b.ymin),
            ymax: a.ymax.max(b.ymax),
            count: a.count.saturating_add(b.count),
        }),
        (a, b) => a.or(b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::processors::testing::{cut, frame, params, square, template};
    use crate::types::Decimation;

    #[test]
    fn motion_is_reported_with_the_template_captured_once() {
        let region = square(0, 0, 64, Decimation::Full);
        let mut prev = [0u8; 64 * 64];
        let mut w = Watch::new(region, &mut prev, params(), false);
        assert_eq!(w.start().request, Some(region));
        // The first window has nothing to difference against.
        let blank = frame(None);
        let s = w.on_window(&cut(&blank, &region));
        assert_eq!((s.work, s.request, s.sends.len()), (Work::Motion { pixels: 4096 }, Some(region), 0));
        // The 4x4 block appears at columns 30..=33, rows 20..=23: 16 pixels differ by 150.
        let block = frame(Some((30, 20)));
        let s = w.on_window(&cut(&block, &region));
        let motion = Msg::Motion { xmin: 30, xmax: 33, ymin: 20, ymax: 23 };
        let want = [
            (Dest::Peripheral, Msg::Template(template())),
            (Dest::Foveal, Msg::Template(template())),
            (Dest::Peripheral, motion),
        ];
        assert_eq!(&s.sends[..], &want[..]);
        // Nothing moved.
        assert!(w.on_window(&cut(&block, &region)).sends.is_empty());
        // The block moves 4 px right: its old and new places differ; no second template.
        let moved = frame(Some((34, 20)));
        let s = w.on_window(&cut(&moved, &region));
        assert_eq!(&s.sends[..], &[(Dest::Peripheral, Msg::Motion { xmin: 30, xmax: 37, ymin: 20, ymax: 23 })][..]);
    }

    #[test]
    fn motion_under_the_pixel_count_is_not_reported() {
        let region = square(0, 0, 64, Decimation::Full);
        let mut prev = [0u8; 64 * 64];
        let p = Params { motion_min_pixels: 17, ..params() };
        let mut w = Watch::new(region, &mut prev, p, true);
        let (blank, block) = (frame(None), frame(Some((30, 20))));
        w.on_window(&cut(&blank, &region));
        // 16 moving pixels, 17 needed.
        assert!(w.on_window(&cut(&block, &region)).sends.is_empty());
    }
}
