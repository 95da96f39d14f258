//! Window confidence measures and the COOP decision (thesis 4.3, and 5.2 future work).
//!
//! **Least squares (4.3).** For the last `n` samples (`3 <= n <= 8`) of a source, with
//! `p_i = sqrt(x_i² + y_i²)`, the line `p̂ = a t + b` has
//! `SS_pt = Σ t_i p_i - Σt_i Σp_i / n`, `SS_tt = Σ t_i² - (Σ t_i)² / n`,
//! `a = SS_pt / SS_tt`, `b = Σp_i / n - a Σt_i / n`, and `SSE = Σ (p_i - p̂_i)²`.
//! The COOP decision takes the source (NCC or corner detector) with the lower SSE.
//! (Times and distances are shifted by the oldest sample's before summing, in `f32`;
//! `a` and `SSE` are unchanged by the shift and `b` is shifted back, which avoids
//! cancellation for large time stamps and distances.)
//!
//! **Kalman filter (beyond the thesis, its 5.2 proposal).** Each source feeds a
//! constant-velocity Kalman filter per axis; the score is an exponential moving average
//! of the innovation magnitude `|z - H x̂⁻|`, and the source with the lower score wins.
//!
//! Both policies implement [`ConfidencePolicy`]. Non-finite samples are rejected, so no
//! score is ever NaN.

use crate::kernels::fmath::sqrtf;
use crate::types::Source;
use heapless::Deque;

/// Largest data set of the least-squares measure.
pub const MAX_SAMPLES: usize = 8;

/// Why a policy or sample was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConfidenceError {
    /// Data set size outside `3..=8`, or non-positive / non-finite filter parameters.
    BadParameter,
    /// A time or coordinate is NaN or infinite.
    NonFinite,
    /// The time does not increase (Kalman policy needs `dt > 0`).
    TimeNotIncreasing,
}

error_messages!(ConfidenceError {
    BadParameter => "the data set size must be 3 to 8, and filter parameters positive and finite",
    NonFinite => "a time or coordinate is not a finite number",
    TimeNotIncreasing => "times must increase from one sample to the next",
});

/// A least-squares line `p̂ = a t + b` and its sum of squared errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineFit {
    /// Slope `SS_pt / SS_tt`.
    pub a: f64,
    /// Intercept `Σp/n - a Σt/n`.
    pub b: f64,
    /// `Σ (p_i - p̂_i)²`.
    pub sse: f64,
}

/// The last `n` samples `(t_i, p_i)` of one source.
#[derive(Clone, Debug)]
pub struct LsqTrack {
    n: usize,
    /// `(t_i, p_i)`: the time and the distance from the origin.
    samples: Deque<(f64, f32), MAX_SAMPLES>,
}

impl LsqTrack {
    /// A track of data set size `n` in `3..=8` (the thesis found 4 best, Table 4.1).
    pub fn new(n: usize) -> Result<Self, ConfidenceError> {
        if !(3..=MAX_SAMPLES).contains(&n) {
            return Err(ConfidenceError::BadParameter);
        }
        Ok(Self { n, samples: Deque::new() })
    }

    /// Adds the position `(x, y)` at time `t` as `p = sqrt(x² + y²)` (in `f32`, as the
    /// positions are), dropping the oldest sample beyond `n`.
    pub fn push(&mut self, t: f64, x: f64, y: f64) -> Result<(), ConfidenceError> {
        let (x, y) = (x as f32, y as f32);
        let p = sqrtf(x * x + y * y);
        if !t.is_finite() || !p.is_finite() {
            return Err(ConfidenceError::NonFinite);
        }
        if self.samples.len() >= self.n {
            self.samples.pop_front();
        }
        // Cannot fail: the length is below n <= capacity after the pop.
        let _ = self.samples.push_back((t, p));
        Ok(())
    }

    /// The least-squares line over the last `n` samples; `None` until `n` samples are
    /// in, or if all times are equal (`SS_tt = 0`).
    pub fn fit(&self) -> Option<LineFit> {
        if self.samples.len() < self.n {
            return None;
        }
        let mut buf = [(0.0, 0.0); MAX_SAMPLES];
        for (d, s) in buf.iter_mut().zip(self.samples.iter()) {
            *d = *s;
        }
        least_squares(buf.get(..self.samples.len())?)
    }
}

/// The thesis 4.3 least-squares line of `(t_i, p_i)` samples; `None` for fewer than two
/// or more than [`MAX_SAMPLES`] samples, `SS_tt = 0`, or a non-finite result.
///
/// The sums are `f32`, as the C40 computed (2.6: 32-bit floating point), on the Cortex-M4F's
/// FPU; `f64` is software there and took 5 times the instructions. Times and distances are
/// taken from the first sample's (the only `f64` work), which leaves small values: no
/// cancellation in `SS_pt` or `SS_tt`, whatever the time stamps or the distance.
pub fn least_squares(samples: &[(f64, f32)]) -> Option<LineFit> {
    let &(t0, p0) = samples.first()?;
    let (mut st, mut sp, mut stp, mut stt) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    let mut shifted = [(0.0f32, 0.0f32); MAX_SAMPLES];
    for (d, &(t, p)) in shifted.iter_mut().zip(samples) {
        let (t, p) = ((t - t0) as f32, p - p0);
        *d = (t, p);
        st += t;
        sp += p;
        stp += t * p;
        stt += t * t;
    }
    let shifted = shifted.get(..samples.len())?;
    let n = samples.len() as f32;
    if n < 2.0 {
        return None;
    }
    let ss_pt = stp - st * sp / n;
    let ss_tt = stt - st * st / n;
    if ss_tt.is_nan() || ss_tt <= 0.0 {
        return None;
    }
    let a = ss_pt / ss_tt;
    let b_shifted = sp / n - a * st / n;
    let sse: f32 = shifted.iter().map(|&(t, p)| (p - (a * t + b_shifted)) * (p - (a * t + b_shifted))).sum();
    let (a, b) = (f64::from(a), f64::from(p0 + b_shifted));
    let b = b - a * t0;
    (a.is_finite() && b.is_finite() && sse.is_finite()).then_some(LineFit { a, b, sse: f64::from(sse) })
}

/// A confidence policy of the cooperative Foveal windows: it is fed the positions of
/// both sources and chooses the one to follow.
pub trait ConfidencePolicy {
    /// Records the position `(x, y)` reported by `src` at time `t`.
    fn push(&mut self, src: Source, t: f64, x: f64, y: f64) -> Result<(), ConfidenceError>;
    /// The source to update the Foveal windows from.
    fn choose(&self) -> Source;
}

/// Lower score wins; a source without a score loses to one with; NCC by default and on
/// ties (it is the thesis' primary Foveal algorithm).
fn lower(ncc: Option<f64>, cd: Option<f64>) -> Source {
    match (ncc, cd) {
        (Some(n), Some(c)) if c < n => Source::Cd,
        (None, Some(_)) => Source::Cd,
        _ => Source::Ncc,
    }
}

/// The thesis' COOP decision: the source whose last `n` positions have the lower SSE
/// about their least-squares line (4.3).
#[derive(Clone, Debug)]
pub struct SseCoop {
    ncc: LsqTrack,
    cd: LsqTrack,
}

impl SseCoop {
    /// COOP with data set size `n` in `3..=8`.
    pub fn new(n: usize) -> Result<Self, ConfidenceError> {
        Ok(Self { ncc: LsqTrack::new(n)?, cd: LsqTrack::new(n)? })
    }

    /// COOP with the thesis's data set size, 4 (4.4).
    pub fn thesis() -> Self {
        Self { ncc: LsqTrack { n: 4, samples: Deque::new() }, cd: LsqTrack { n: 4, samples: Deque::new() } }
    }

    /// The current fit of one source.
    pub fn fit(&self, src: Source) -> Option<LineFit> {
        match src {
            Source::Ncc => self.ncc.fit(),
            Source::Cd => self.cd.fit(),
        }
    }
}

impl ConfidencePolicy for SseCoop {
    fn push(&mut self, src: Source, t: f64, x: f64, y: f64) -> Result<(), ConfidenceError> {
        match src {
            Source::Ncc => self.ncc.push(t, x, y),
            Source::Cd => self.cd.push(t, x, y),
        }
    }

    fn choose(&self) -> Source {
        lower(self.ncc.fit().map(|f| f.sse), self.cd.fit().map(|f| f.sse))
    }
}

/// Constant-velocity Kalman filter of one axis: state `(position, velocity)`.
#[derive(Clone, Copy, Debug)]
struct Axis {
    x: [f64; 2],
    p: [[f64; 2]; 2],
}

impl Axis {
    fn new(z: f64, r: f64) -> Self {
        // Position known to the measurement noise, velocity unknown (large variance).
        Self { x: [z, 0.0], p: [[r, 0.0], [0.0, 1.0e6]] }
    }

    /// Predict over `dt` with white-acceleration noise `q`, update with `z`; returns the
    /// innovation `z - x̂⁻`.
    fn step(&mut self, dt: f64, z: f64, q: f64, r: f64) -> f64 {
        let [[p00, p01], [p10, p11]] = self.p;
        // x⁻ = F x, P⁻ = F P Fᵀ + Q with F = [1 dt; 0 1], Q = q [dt³/3 dt²/2; dt²/2 dt].
        let xp = [self.x[0] + dt * self.x[1], self.x[1]];
        let a00 = p00 + dt * (p01 + p10) + dt * dt * p11 + q * dt * dt * dt / 3.0;
        let a01 = p01 + dt * p11 + q * dt * dt / 2.0;
        let a10 = p10 + dt * p11 + q * dt * dt / 2.0;
        let a11 = p11 + q * dt;
        let innov = z - xp[0];
        let s = a00 + r;
        let (k0, k1) = (a00 / s, a10 / s);
        self.x = [xp[0] + k0 * innov, xp[1] + k1 * innov];
        self.p = [[(1.0 - k0) * a00, (1.0 - k0) * a01], [a10 - k1 * a00, a11 - k1 * a01]];
        innov
    }

    fn is_finite(&self) -> bool {
        self.x.iter().chain(self.p.iter().flatten()).all(|v| v.is_finite())
    }
}

/// One source's filter and its smoothed innovation magnitude.
#[derive(Clone, Copy, Debug)]
struct Track {
    t: f64,
    ax: Axis,
    ay: Axis,
    score: Option<f64>,
}

/// The Kalman-filter confidence policy: the source with the lower exponentially
/// averaged innovation magnitude `|(z_x - x̂⁻_x, z_y - x̂⁻_y)|` wins.
#[derive(Clone, Debug)]
pub struct KalmanCoop {
    q: f64,
    r: f64,
    alpha: f64,
    ncc: Option<Track>,
    cd: Option<Track>,
}

impl KalmanCoop {
    /// Process noise `q` (acceleration spectral density, px²/s³), measurement noise `r`
    /// (px²) and averaging weight `alpha` in `(0, 1]` of the newest innovation.
    pub fn new(q: f64, r: f64, alpha: f64) -> Result<Self, ConfidenceError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !ok(q) || !ok(r) || !ok(alpha) || alpha > 1.0 {
            return Err(ConfidenceError::BadParameter);
        }
        Ok(Self { q, r, alpha, ncc: None, cd: None })
    }

    /// The smoothed innovation magnitude of a source (`None` before its second sample).
    pub fn score(&self, src: Source) -> Option<f64> {
        match src {
            Source::Ncc => self.ncc.and_then(|t| t.score),
            Source::Cd => self.cd.and_then(|t| t.score),
        }
    }
}

impl ConfidencePolicy for KalmanCoop {
    fn push(&mut self, src: Source, t: f64, x: f64, y: f64) -> Result<(), ConfidenceError> {
        if !(t.is_finite() && x.is_finite() && y.is_finite()) {
            return Err(ConfidenceError::NonFinite);
        }
        let (q, r, alpha) = (self.q, self.r, self.alpha);
        let slot = match src {
            Source::Ncc => &mut self.ncc,
            Source::Cd => &mut self.cd,
        };
        let Some(tr) = slot else {
            *slot = Some(Track { t, ax: Axis::new(x, r), ay: Axis::new(y, r), score: None });
            return Ok(());
        };
        let dt = t - tr.t;
        if dt.is_nan() || dt <= 0.0 {
            return Err(ConfidenceError::TimeNotIncreasing);
        }
        let (mut ax, mut ay) = (tr.ax, tr.ay);
        let (ix, iy) = (ax.step(dt, x, q, r), ay.step(dt, y, q, r));
        let mag = libm::sqrt(ix * ix + iy * iy);
        if !(ax.is_finite() && ay.is_finite() && mag.is_finite()) {
            // Overflow for absurd time gaps: restart the filter at the measurement.
            *tr = Track { t, ax: Axis::new(x, r), ay: Axis::new(y, r), score: tr.score };
            return Ok(());
        }
        let score = tr.score.map_or(mag, |s| s + alpha * (mag - s));
        *tr = Track { t, ax, ay, score: Some(score) };
        Ok(())
    }

    fn choose(&self) -> Source {
        lower(self.score(Source::Ncc), self.score(Source::Cd))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_formulas_by_hand() {
        // p = 3, 5, 4 at t = 1, 2, 3 (x = p, y = 0):
        // Σt = 6, Σp = 12, Σtp = 25, Σt² = 14; SS_pt = 25 - 24 = 1, SS_tt = 14 - 12 = 2;
        // a = 0.5, b = 4 - 1 = 3; p̂ = 3.5, 4, 4.5; SSE = 0.25 + 1 + 0.25 = 1.5.
        let mut tr = LsqTrack::new(3).unwrap();
        for (t, p) in [(1.0, 3.0), (2.0, 5.0), (3.0, 4.0)] {
            tr.push(t, p, 0.0).unwrap();
        }
        let f = tr.fit().unwrap();
        assert!((f.a - 0.5).abs() < 1e-6 && (f.b - 3.0).abs() < 1e-6 && (f.sse - 1.5).abs() < 1e-6);
        // p = sqrt(x² + y²): (3, 4) -> 5; window slides to t = 2, 3, 4 with p = 5, 4, 5.
        tr.push(4.0, 3.0, 4.0).unwrap();
        let f = tr.fit().unwrap();
        // Σt = 9, Σp = 14, Σtp = 10 + 12 + 20 = 42, Σt² = 29: SS_pt = 0, a = 0, SSE = 2/3.
        assert!(f.a.abs() < 1e-6 && (f.sse - 2.0 / 3.0).abs() < 1e-6);
        assert_eq!(LsqTrack::new(2).err(), Some(ConfidenceError::BadParameter));
        assert_eq!(LsqTrack::new(9).err(), Some(ConfidenceError::BadParameter));
        assert_eq!(tr.push(f64::NAN, 0.0, 0.0), Err(ConfidenceError::NonFinite));
    }

    #[test]
    fn equal_times_have_no_fit() {
        assert_eq!(least_squares(&[(1.0, 1.0), (1.0, 2.0), (1.0, 3.0)]), None);
    }

    #[test]
    fn coop_prefers_the_smoother_source() {
        let mut c = SseCoop::new(4).unwrap();
        assert_eq!(c.choose(), Source::Ncc);
        for i in 0..4 {
            let t = f64::from(i);
            c.push(Source::Ncc, t, 10.0 + t + if i % 2 == 0 { 2.0 } else { -2.0 }, 0.0).unwrap();
            c.push(Source::Cd, t, 10.0 + t, 0.0).unwrap();
        }
        assert_eq!(c.choose(), Source::Cd);
        assert!(c.fit(Source::Cd).unwrap().sse < 1e-10);
    }

    #[test]
    fn kalman_tracks_constant_velocity_and_prefers_smooth() {
        let mut k = KalmanCoop::new(1.0, 1.0, 0.5).unwrap();
        for i in 0..20 {
            let t = f64::from(i) * 0.01;
            k.push(Source::Cd, t, 100.0 + 50.0 * t, 20.0).unwrap();
            let jitter = if i % 2 == 0 { 3.0 } else { -3.0 };
            k.push(Source::Ncc, t, 100.0 + 50.0 * t + jitter, 20.0).unwrap();
        }
        assert!(k.score(Source::Cd).unwrap() < 0.5);
        assert_eq!(k.choose(), Source::Cd);
        assert_eq!(k.push(Source::Cd, 0.0, 0.0, 0.0), Err(ConfidenceError::TimeNotIncreasing));
        assert!(KalmanCoop::new(0.0, 1.0, 0.5).is_err());
    }
}
