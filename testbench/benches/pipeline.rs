//! Whole-pipeline speed: each strategy (and `track`'s default, COOP adapting) tracking a
//! pre-rendered 120-frame scene with the `native` cost profile, in frames per second
//! (criterion's throughput). Scene rendering is done once, outside the measurement. Run: cargo bench -p coopwin-testbench --bench pipeline
use coopwin_testbench::experiments::setup::triangle;
use coopwin_testbench::frames::prerendered::Prerendered;
use coopwin_testbench::frames::scene::SceneConfig;
use coopwin_testbench::system::cost::CostModel;
use coopwin_testbench::system::{simulate, Strategy, SystemConfig};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn pipeline(c: &mut Criterion) {
    let cfg = SceneConfig { frames: 120, ..triangle(60.0, 1) };
    let mut frames = Prerendered::new(&cfg);
    let target = frames.truth[0].corner;
    let mut g = c.benchmark_group("pipeline_native");
    g.throughput(Throughput::Elements(cfg.frames as u64));
    g.sample_size(10);
    for s in [Strategy::Spmf, Strategy::Tpdf, Strategy::Mpdf, Strategy::Coop] {
        let sys = SystemConfig::thesis(s, CostModel::NATIVE, Some(target));
        g.bench_function(s.name(), |b| b.iter(|| simulate(&sys, &mut frames, &mut |_| {}).expect("run")));
    }
    // `track`'s default: COOP with the adapting template (issue 21), against KCF's time a frame
    // (scripts/tracker_speed.py on the same scene; fixtures/bench/README.md).
    let mut adapting = SystemConfig::thesis(Strategy::Coop, CostModel::NATIVE, Some(target));
    adapting.params = adapting.params.adaptive();
    g.bench_function("COOP adapting", |b| b.iter(|| simulate(&adapting, &mut frames, &mut |_| {}).expect("run")));
    g.finish();
}

criterion_group!(benches, pipeline);
criterion_main!(benches);
