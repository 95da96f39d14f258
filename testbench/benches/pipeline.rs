//! Whole-pipeline speed: each strategy tracking a pre-rendered 120-frame scene with the
//! `native` cost profile, in frames per second (criterion's throughput). Scene rendering is
//! done once, outside the measurement. Run: cargo bench -p coopwin-testbench --bench pipeline
use coopwin_testbench::cost::CostModel;
use coopwin_testbench::experiments::{system, triangle};
use coopwin_testbench::scene::{Scene, SceneConfig};
use coopwin_testbench::system::{run, FrameSource, Strategy};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

struct Frames<'a>(&'a [Vec<u8>]);

impl FrameSource for Frames<'_> {
    fn size(&self) -> (usize, usize) {
        (256, 256)
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], String> {
        self.0.get(k).map(|f| f.as_slice()).ok_or_else(|| format!("no frame {k}"))
    }
}

fn pipeline(c: &mut Criterion) {
    let cfg = SceneConfig { frames: 120, ..triangle(60.0, 1) };
    let scene = Scene::new(cfg.clone());
    let frames: Vec<Vec<u8>> = (0..cfg.frames).map(|k| scene.render(k).0).collect();
    let target = scene.truth(0).corner;
    let mut g = c.benchmark_group("pipeline_native");
    g.throughput(Throughput::Elements(cfg.frames as u64));
    g.sample_size(10);
    for s in [Strategy::Spmf, Strategy::Tpdf, Strategy::Mpdf, Strategy::Coop] {
        let sys = system(s, CostModel::NATIVE, Some(target));
        g.bench_function(s.name(), |b| {
            b.iter(|| {
                let mut src = Frames(&frames);
                run(&sys, &mut src, &mut |_| {}).expect("run")
            })
        });
    }
    g.finish();
}

criterion_group!(benches, pipeline);
criterion_main!(benches);
