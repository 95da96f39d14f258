//! What a run's results mean: tracking figures against ground truth ([`metrics`], thesis 2.4,
//! 3.4, 4.4), the peak-to-sidelobe baseline for a confidence ([`psr`]) and the waveform audit
//! of a traced run ([`audit`], Appendix B).
pub mod audit;
pub mod longterm;
pub mod metrics;
pub mod psr;
