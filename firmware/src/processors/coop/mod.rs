//! The COOP master's decision (thesis 4.2-4.3, 5.2): which of the two Foveal sources, NCC and
//! the corner detector, a cooperative track follows each frame.
//!
//! - [`guard`]: guarded cooperation, the default: the corner detector only where it measures
//!   the tracked point (beyond the thesis, for real imagery);
//! - the thesis's least-squares SSE rule (4.3) and the Kalman filter it proposes (5.2), both in
//!   [`crate::kernels::confidence`].
pub mod guard;

use crate::kernels::confidence::{ConfidencePolicy, KalmanCoop, SseCoop};
use crate::types::{Point, Source};
use guard::{Guard, Measured};


/// The COOP master's decision: guarded cooperation (the default), the thesis's
/// least-squares SSE (4.3), or the Kalman filter it proposes as future work (5.2).
#[derive(Clone, Debug)]
// No allocator to box the guard into: each policy lives inline in its processor.
#[allow(clippy::large_enum_variant)]
pub enum Policy {
    /// CD only where it measures the tracked point ([`guard`]).
    Guarded(Guard),
    /// Lower SSE about the least-squares line of the last n positions wins.
    Sse(SseCoop),
    /// Lower smoothed Kalman innovation wins.
    Kalman(KalmanCoop),
}

impl Policy {
    /// The position to follow for one window's measurements.
    pub(super) fn decide(&mut self, t: f64, m: Measured) -> Option<(Point, Source)> {
        let Measured { ncc, corner, .. } = m;
        let smooth: &mut dyn ConfidencePolicy = match self {
            Policy::Guarded(g) => {
                return g.decide(t, m);
            }
            Policy::Sse(p) => p,
            Policy::Kalman(p) => p,
        };
        let own = ncc.map(|(p, _)| p);
        // A rejected (non-finite) sample leaves that source's history as it was.
        if let Some(p) = own {
            let _ = smooth.push(Source::Ncc, t, f64::from(p.x), f64::from(p.y));
        }
        if let Some(p) = corner {
            let _ = smooth.push(Source::Cd, t, f64::from(p.x), f64::from(p.y));
        }
        match (smooth.choose(), own, corner) {
            (Source::Ncc, Some(p), _) | (Source::Cd, Some(p), None) => Some((p, Source::Ncc)),
            (Source::Cd, _, Some(p)) | (Source::Ncc, None, Some(p)) => Some((p, Source::Cd)),
            _ => None,
        }
    }

    /// After a window with no position: where a coasting track looks next (see
    /// [`Guard::coast`]); the thesis's policies do not coast.
    pub(super) fn coast(&mut self, t: f64) -> Option<Point> {
        match self {
            Policy::Guarded(g) => g.coast(t),
            Policy::Sse(_) | Policy::Kalman(_) => None,
        }
    }

    /// Where the followed point should be one window interval after `t` (see
    /// [`Guard::ahead`]); the thesis's policies do not predict.
    pub(super) fn ahead(&self, t: f64) -> Option<Point> {
        match self {
            Policy::Guarded(g) => g.ahead(t),
            Policy::Sse(_) | Policy::Kalman(_) => None,
        }
    }

    /// A track starts at `p` (see [`Guard::begin`]).
    pub(super) fn begin(&mut self, p: Point, exact: bool) {
        if let Policy::Guarded(g) = self {
            g.begin(p, exact);
        }
    }
}
