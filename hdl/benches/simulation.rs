//! Simulation speed of the window unit for one CA-D1 frame (70 192 pixel clocks), in pixel
//! clocks per second (criterion's throughput): the direct-stepping driver used for long runs,
//! and rust-hdl's thread-based `Simulation` used for the VCD and Appendix B tests.
//! Run: cargo bench -p coopwin-hdl --bench simulation
use coopwin_hdl::sim::appendix_b::simulate_acquisition;
use coopwin_hdl::sim::camera::{RasterTiming, Window};
use coopwin_hdl::sim::run::{run_unit, Request};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::sync::Arc;

fn frame_speed(c: &mut Criterion) {
    let t = RasterTiming::CA_D1;
    let frame: Vec<u8> = (0..65536u32).map(|i| (i * 7) as u8).collect();
    let w = Window { xmin: 100, xmax: 139, ymin: 100, ymax: 139 };
    let mut g = c.benchmark_group("window_unit_frame");
    g.throughput(Throughput::Elements(t.frame_clocks() as u64));
    g.sample_size(10);
    g.bench_function("direct_stepping", |b| {
        let frames = vec![frame.clone()];
        b.iter(|| run_unit::<8, 8>(&t, &frames, &[Request { at: 0, window: w, decimate: false }]))
    });
    // The Appendix B run spans the blanking before the frame and two lines after it.
    g.throughput(Throughput::Elements((t.frame_clocks() + 2 * t.line_clocks()) as u64));
    g.bench_function("rust_hdl_simulation", |b| {
        let image = Arc::new(frame.iter().map(|&p| u16::from(p)).collect::<Vec<u16>>());
        b.iter(|| simulate_acquisition::<8, 8>(t, w, false, 1, image.clone()).expect("sim"))
    });
    g.finish();
}

criterion_group!(benches, frame_speed);
criterion_main!(benches);
