//! Sub-pixel position of the best placement (thesis 2.4 beyond whole pixels).
//!
//! Around the best placement `s0` with neighbours `s-` and `s+` along x (then y), the
//! parabola through the three scores has its vertex at
//! `d = (s- - s+) / (2 (s- - 2 s0 + s+))`. The offset is used only when the parabola
//! opens the right way (downwards for NCC/ZNCC, upwards for SSD/SAD) and is clamped to
//! `[-0.5, 0.5]`; at the window border or for a flat neighbourhood it is 0.

/// Parabola vertex offset through `(−1, l), (0, c), (1, r)`, or 0 when the parabola
/// does not open towards the optimum or a neighbour is missing.
pub(crate) fn parabola(l: Option<f64>, c: f64, r: Option<f64>, maximise: bool) -> f64 {
    let (Some(l), Some(r)) = (l, r) else {
        return 0.0;
    };
    let curv = l - 2.0 * c + r;
    let opens_right = if maximise { curv < 0.0 } else { curv > 0.0 };
    if !opens_right {
        return 0.0;
    }
    let d = (l - r) / (2.0 * curv);
    if d.is_finite() {
        d.clamp(-0.5, 0.5)
    } else {
        0.0
    }
}

