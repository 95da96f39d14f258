//! Information content measures for the corner detector (thesis 3.4.1).
//!
//! The thesis defines the edge-pixel information content `I = -log2 P` (eq. 3.2, after
//! \[Bhanu86\]) with `P` "the probability of possible pictures made up of edge pixels",
//! without saying how `P` is computed. This module makes it explicit:
//!
//! * each of the `N` window pixels is independently an edge with probability `p`;
//! * the observed edge picture has `n` edge pixels, so its probability is the binomial
//!   term `P = p^n (1-p)^(N-n)` and `I = -n log2 p - (N-n) log2 (1-p)` bits;
//! * [`edge_information`] uses the maximum-likelihood `p = n/N` (then `I = N·H2(n/N)`,
//!   0 for an empty or a full window, maximal `N` bits at `n = N/2`);
//! * [`edge_information_with_prior`] takes a fixed prior `p` (e.g. the edge density
//!   expected at threshold TH); for `p < 1/2` it grows with `n`, the behaviour the thesis
//!   describes ("a high value for a large number of edge pixels").
//!
//! The thesis' own measure is `I_cd = 1 / CLERR` ([`corner_information`]), the inverse
//! of the corner location error observed for a given number of edge pixels.

/// `I = -log2(p^n (1-p)^(N-n))` with `p = n/N` (`0·log 0 = 0`), in bits. Returns 0 for
/// `N = 0` and clamps `n` to `N`.
pub fn edge_information(n: u32, total: u32) -> f64 {
    if total == 0 {
        return 0.0;
    }
    let n = n.min(total);
    edge_information_with_prior(n, total, f64::from(n) / f64::from(total)).unwrap_or(0.0)
}

/// `I = -n log2 p - (N-n) log2(1-p)` bits for a prior edge probability `p` in `[0, 1]`;
/// `None` if `p` is outside `[0, 1]` (or NaN), or if the picture is impossible under
/// `p` (`p = 0` with edges, `p = 1` with non-edges: infinite information). `n` is
/// clamped to `N`.
pub fn edge_information_with_prior(n: u32, total: u32, p: f64) -> Option<f64> {
    if !(0.0..=1.0).contains(&p) {
        return None;
    }
    let n = n.min(total);
    let bits = |count: u32, prob: f64| -> Option<f64> {
        if count == 0 {
            Some(0.0)
        } else if prob <= 0.0 {
            None
        } else {
            Some(-f64::from(count) * libm::log2(prob))
        }
    };
    Some(bits(n, p)? + bits(total - n, 1.0 - p)?)
}

/// The thesis' corner-detection information `I_cd = 1 / CLERR` (3.4.1), with CLERR the
/// corner location error in pixels. `None` unless `CLERR` is finite and positive.
pub fn corner_information(clerr: f64) -> Option<f64> {
    (clerr.is_finite() && clerr > 0.0).then(|| 1.0 / clerr)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_values() {
        // n = 2 of N = 4: p = 1/2, I = 4 bits.
        assert!((edge_information(2, 4) - 4.0).abs() < 1e-12);
        // n = 1 of N = 4: I = -log2(1/4) - 3 log2(3/4) = 2 + 1.2451124978 bits.
        assert!((edge_information(1, 4) - (2.0 + 3.0 * (4.0f64 / 3.0).log2())).abs() < 1e-12);
        assert_eq!(edge_information(0, 400), 0.0);
        assert_eq!(edge_information(400, 400), 0.0);
        assert_eq!(edge_information(3, 0), 0.0);
        // Prior p = 1/8, 1 edge of 2: 3 + log2(8/7) bits.
        let i = edge_information_with_prior(1, 2, 0.125).unwrap();
        assert!((i - (3.0 + (8.0f64 / 7.0).log2())).abs() < 1e-12);
        assert_eq!(edge_information_with_prior(1, 2, 0.0), None);
        assert_eq!(edge_information_with_prior(1, 2, f64::NAN), None);
        assert_eq!(corner_information(0.5), Some(2.0));
        assert_eq!(corner_information(0.0), None);
    }
}
