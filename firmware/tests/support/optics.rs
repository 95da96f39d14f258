//! The camera's optics for rendered test scenes: a 3x3 box blur (clamped at the border) of an
//! `n` x `n` coverage map, plus per-pixel noise, rounded to 8 bits.

/// `cov` blurred and with `noise()` added to each pixel, as 8-bit gray.
pub fn blur_and_quantise(cov: &[f64], n: usize, mut noise: impl FnMut() -> f64) -> Vec<u8> {
    let at = |x: i64, y: i64| cov[y.clamp(0, n as i64 - 1) as usize * n + x.clamp(0, n as i64 - 1) as usize];
    let mut out = vec![0u8; n * n];
    for j in 0..n {
        for i in 0..n {
            let acc: f64 = (-1i64..=1).flat_map(|dj| (-1i64..=1).map(move |di| (di, dj))).map(|(di, dj)| at(i as i64 + di, j as i64 + dj)).sum();
            out[j * n + i] = (acc / 9.0 + noise()).round().clamp(0.0, 255.0) as u8;
        }
    }
    out
}
