//! The vocabulary shared by the kernels, the processors and the ports.

/// A point in frame coordinates (pixel centres at integers).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Point {
    /// Column.
    pub x: f32,
    /// Row.
    pub y: f32,
}
