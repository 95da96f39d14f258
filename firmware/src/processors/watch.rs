//! The Watch processor (thesis 2.3.1, 2.4): image differencing over the whole frame or one of
//! MPDF's strips, reporting the motion area and capturing the template at the first motion.
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
        Step::new(Work::None).ask(Some(self.region))
    }

    /// A Watch window arrived.
    pub fn on_window(&mut self, win: &WindowView<'_>) -> Step {
        let pixels = (win.width() * win.height()) as u32;
        let mut step = Step::new(Work::Motion { pixels }).ask(Some(self.region));
        let Some(prev_buf) = self.prev.get(..pixels as usize) else { return step };
        if self.have_prev {
            let (ox, oy) = win.origin();
            let prev = WindowView::new(prev_buf, win.width(), win.height(), win.width(), ox, oy);
            if let Ok(prev) = prev {
                if let Ok(Some(area)) = detect_motion(&prev, win, self.params.motion_threshold) {
                    if area.count >= self.params.motion_min_pixels {
                        step = self.report(step, win, area);
                    }
                }
            }
        }
        if win.pack_into(self.prev).is_some() {
            self.have_prev = true;
        }
        step
    }

    fn report(&mut self, step: Step, win: &WindowView<'_>, a: MotionArea) -> Step {
        let c = Point { x: (a.xmin + a.xmax) as f32 / 2.0, y: (a.ymin + a.ymax) as f32 / 2.0 };
        let mut step = step;
        if !self.template_sent {
            if let Some(t) = Template::capture(win, c, self.params.template as usize) {
                self.template_sent = true;
                step = step.send(Dest::Peripheral, Msg::Template(t.clone())).send(Dest::Foveal, Msg::Template(t));
            }
        }
        step.send(
            Dest::Peripheral,
            Msg::Motion { xmin: a.xmin as u16, xmax: a.xmax as u16, ymin: a.ymin as u16, ymax: a.ymax as u16 },
        )
    }
}
