//! The vocabulary shared by the kernels, the processors and the ports: a point in the frame,
//! a window to acquire (thesis 2.2.1: bounds and decimation written to the window unit), and
//! which Foveal algorithm produced a position (thesis 4.2). Nothing here depends on another
//! module of the crate.

/// A point in frame coordinates (pixel centres at integers).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Point {
    /// Column.
    pub x: f32,
    /// Row.
    pub y: f32,
}

/// How the tracked object looks against its first view (issue 21): turned and scaled, as an
/// adapting track measures by aligning its first template ([`crate::kernels::warp`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// The object's size over its size at lock-on.
    pub scale: f32,
    /// Its turn since lock-on, degrees, clockwise on the screen (rows grow down).
    pub angle_deg: f32,
}

/// Resolution of a requested window (thesis 2.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decimation {
    /// Every pixel.
    Full,
    /// 25 %: every other pixel of every other row.
    Quarter,
}

/// A window to acquire, in frame coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowRequest {
    /// Left column.
    pub x0: u16,
    /// Top row.
    pub y0: u16,
    /// Width in frame pixels.
    pub width: u16,
    /// Height in frame pixels.
    pub height: u16,
    /// Resolution of the delivered pixels.
    pub decimation: Decimation,
}

impl WindowRequest {
    /// Width and height of the delivered pixel block.
    pub fn delivered_size(&self) -> (usize, usize) {
        let (w, h) = (usize::from(self.width), usize::from(self.height));
        match self.decimation {
            Decimation::Full => (w, h),
            Decimation::Quarter => (w.div_ceil(2), h.div_ceil(2)),
        }
    }
}

/// The algorithm that measured a tracked position: the two sources of the cooperative Foveal
/// windows (thesis 4.2), which the COOP decision chooses between and the robot is told.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Normalised cross-correlation (Fw2 in the thesis).
    Ncc,
    /// Corner detector (Fw1).
    Cd,
}
