//! Where the hardware-in-the-loop backends spend their time: one CA-D1 frame (70 192 pixel
//! clocks) of the 4-unit network with idle coordinate ports, stepped bare (the simulator
//! alone: Verilator's model through its C interface, or four rust-hdl units stepped directly),
//! against the camera raster alone. Throughput is in pixel clocks.
//! Run: cargo bench -p coopwin-testbench --bench backends
use coopwin_hdl::sim::camera::RasterTiming;
use coopwin_hdl::sim::driver::{CoordBus, UnitDriver, UnitOutputs};
use coopwin_hdl::sim::verilator::VerilatorNetwork;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;

fn backends(c: &mut Criterion) {
    let t = RasterTiming::CA_D1;
    let frame: Vec<u8> = (0..65536u32).map(|i| (i * 7) as u8).collect();
    let n = t.frame_clocks();
    let ports = [CoordBus::default(); 4];
    let mut g = c.benchmark_group("network_frame");
    g.throughput(Throughput::Elements(n as u64));
    g.sample_size(10);
    g.bench_function("camera_raster_only", |b| {
        b.iter(|| (0..n).map(|k| t.bus_at(k, |x, y| frame[y * 256 + x]).pixel as u64).sum::<u64>())
    });
    let mut units: Vec<UnitDriver<8, 8>> = (0..4).map(|_| UnitDriver::default()).collect();
    g.bench_function("rust_hdl_4_units", |b| {
        b.iter(|| {
            for k in 0..n {
                let bus = t.bus_at(k, |x, y| frame[y * 256 + x]);
                for u in units.iter_mut() {
                    black_box(u.step(bus, CoordBus::default()));
                }
            }
        })
    });
    match VerilatorNetwork::new(&coopwin_hdl::verilog::Geometry::CA_D1) {
        Ok(mut v) => {
            let mut out = [UnitOutputs::default(); 4];
            g.bench_function("verilator_network", |b| {
                b.iter(|| {
                    for k in 0..n {
                        v.step(t.bus_at(k, |x, y| frame[y * 256 + x]), &ports, &mut out);
                        black_box(&out);
                    }
                })
            });
        }
        Err(e) => eprintln!("SKIPPED verilator_network: {e}"),
    }
    g.finish();
}

criterion_group!(benches, backends);
criterion_main!(benches);
