//! How results are shown: a run's closing lines, summary and verdict ([`summary`]), the CSV files a run
//! writes ([`csv`]), line charts ([`plot`]) and the Appendix B timing diagrams
//! ([`timing_svg`]).
pub mod csv;
pub mod overlay;
pub mod plot;
pub mod summary;
pub mod timing_svg;

pub use summary::{run_lines, summary_table, verdict};

/// Seconds as milliseconds with `decimals` decimals, or `-` for none.
pub fn ms(v: Option<f64>, decimals: usize) -> String {
    v.map(|s| format!("{:.*}", decimals, s * 1e3)).unwrap_or_else(|| "-".into())
}

#[cfg(test)]
mod tests {
    use super::ms;

    #[test]
    fn milliseconds_round_to_the_decimals_asked_for() {
        assert_eq!(ms(Some(0.01234), 0), "12");
        assert_eq!(ms(Some(0.01234), 1), "12.3");
        assert_eq!(ms(None, 1), "-");
    }
}
