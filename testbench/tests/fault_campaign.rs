//! A bounded fault campaign on the tracking loop: 36 runs of 100 frames (3 600 frames) of
//! COOP on the triangle scene, each with faults drawn from a fixed seed: random camera
//! blanking, a window the processor drops, a coordinate set corrupted on its way to the unit,
//! dark frames (a camera dropout), and all of them at once; the robot link's bytes are then
//! corrupted and decoded. Asserted for every run: no panic, no NaN anywhere, every fault
//! logged (a dropped window, a refused set and its watchdog rewrite, a loss of track for a
//! dropout), and tracking recovered after the last fault. The references are the scene's
//! ground truth and, for the link, the reports the run sent. The figures printed at the end
//! are the ones in docs/system.md ("Reliability").
use coopwin_firmware::ports::frame::FrameDecoder;
use coopwin_firmware::ports::position::PositionUpdate;
use coopwin_firmware::processors::Mode;
use coopwin_hdl::sim::camera::Jitter;
use coopwin_testbench::analysis::metrics::summarise;
use coopwin_testbench::experiments::setup::triangle;
use coopwin_testbench::frames::scene::{Scene, SceneConfig, SceneFrames};
use coopwin_testbench::system::cost::CostModel;
use coopwin_testbench::system::{simulate, Strategy, SystemConfig};

const RUNS: u64 = 36;
const FRAMES: usize = 100;
/// Faults start no later than this frame, so every run has time to recover.
const LAST_FAULT: usize = 55;

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        // xorshift64*
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

mod common;
use common::Dropout;

#[derive(Default)]
struct Figures {
    frames: usize,
    blanking_runs: usize,
    dropped: usize,
    refused: usize,
    watchdog: usize,
    dark_frames: usize,
    losses: usize,
    recoveries: Vec<f64>,
    link_bytes: usize,
    link_corrupted: usize,
    link_sent: usize,
    link_accepted: usize,
    rms: Vec<f64>,
    tracked_late: usize,
    corrupted: usize,
    corrupted_logged: usize,
    /// Records whose position was measured in a dark frame.
    from_dark: Vec<String>,
}

#[test]
fn the_loop_survives_every_fault_logs_it_and_recovers() {
    let mut fig = Figures::default();
    for k in 0..RUNS {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ (k + 1).wrapping_mul(0xD1B5_4A32_D192_ED03));
        // Kinds in turn: 0 blanking, 1 dropped window, 2 corrupted set, 3 dark frames, 4 and 5 all.
        let kind = k % 6;
        let all = kind >= 4;
        let scene = SceneConfig { frames: FRAMES, ..triangle(40.0 + rng.below(40) as f64, 100 + k) };
        let truth: Vec<_> = (0..FRAMES).map(|f| Scene::new(scene.clone()).truth(f)).collect();
        let mut cfg = SystemConfig::thesis(Strategy::Coop, CostModel::C40, Some(truth[0].corner));
        if kind == 0 || all {
            cfg.jitter = Some(Jitter { seed: rng.next(), line_max: 1 + rng.below(64) as u32, frame_max: 1 + rng.below(20_000) as u32 });
            fig.blanking_runs += 1;
        }
        // Windows and requests run at about four a frame (COOP's four units).
        if kind == 1 || all {
            cfg.drop_window = Some(20 + rng.below(4 * LAST_FAULT as u64 - 40) as usize);
        }
        if kind == 2 || all {
            cfg.corrupt_request = Some(10 + rng.below(4 * LAST_FAULT as u64 - 40) as usize);
        }
        let dark = if kind == 3 || all {
            let start = 15 + rng.below(LAST_FAULT as u64 - 20) as usize;
            start..start + 1 + rng.below(6) as usize
        } else {
            0..0
        };
        let what = format!("run {k} (kind {kind}): jitter {:?}, drop {:?}, corrupt {:?}, dark {dark:?}", cfg.jitter, cfg.drop_window, cfg.corrupt_request);
        let mut src = Dropout { inner: SceneFrames::new(scene), dark: dark.clone(), zeros: vec![0; 65536] };
        let log = simulate(&cfg, &mut src, &mut |_| {}).unwrap_or_else(|e| panic!("{what}: {e}"));
        let period = log.frame_period;

        // No NaN: every position in the record and every report is finite.
        assert_eq!(log.frames.len(), FRAMES, "{what}");
        for f in &log.frames {
            if let Some((x, y)) = f.point {
                assert!(x.is_finite() && y.is_finite(), "{what}: frame {} at ({x}, {y})", f.frame);
            }
        }
        assert!(log.reports.iter().all(|r| r.point.x.is_finite() && r.point.y.is_finite() && r.t.is_finite()), "{what}");

        // Every fault logged.
        if let Some(i) = cfg.drop_window {
            if i < log.deliveries.len() {
                assert_eq!(log.dropped.len(), 1, "{what}: the dropped window is not logged");
                assert!(!log.watchdog.is_empty(), "{what}: no watchdog rewrite after the dropped window");
            }
        }
        if let Some(i) = cfg.corrupt_request {
            if i < log.requests.len() {
                assert_eq!(log.requests[i].2.width, 1, "{what}: the fault was not injected");
                fig.corrupted += 1;
                if !log.refused.is_empty() || !log.watchdog.is_empty() {
                    fig.corrupted_logged += 1;
                }
            }
        }
        // No position comes from a dark frame, and none is stale: the C40's NCC measures every
        // other frame (two frames), and a dropped window or refused set waits for the
        // watchdog (three more). A track resuming after coasting (frames in Track with no
        // position just before) measured a coasting window, 36x36, whose NCC takes the C40
        // about 15 frame periods.
        for f in &log.frames {
            if let Some(m) = f.measured_frame {
                let resumed = m > 0 && log.frames[m - 1].mode == Mode::Track && log.frames[m - 1].point.is_none();
                let latency = if resumed { 20 } else { 5 };
                assert!(m <= f.frame && m + latency >= f.frame, "{what}: frame {} tracked from frame {m}", f.frame);
                if dark.contains(&m) {
                    fig.from_dark.push(format!("run {k} frame {} ({:?})", f.frame, f.source));
                }
            }
        }
        if dark.len() >= 2 {
            // Two dark frames cannot be measured through: either the loss is logged between the
            // dropout's first frame and two frames after it, or COOP coasts (tracking, with no
            // position) within that stretch.
            let (a, b) = (dark.start as f64 * period, (dark.end + 2) as f64 * period);
            let lost = log.losses.iter().any(|&t| t >= a && t <= b);
            let stretch = log.frames.get(dark.start..(dark.end + 3).min(log.frames.len())).unwrap_or(&[]);
            let coasted = stretch.iter().any(|f| f.mode == Mode::Track && f.point.is_none());
            assert!(lost || coasted, "{what}: the dropout was neither logged as a loss nor coasted through: {:?}", log.losses);
        }
        // Every change from Track to another mode is a logged loss (nothing lost silently).
        for w in log.frames.windows(2) {
            if w[0].mode == Mode::Track && w[1].mode != Mode::Track {
                let (a, b) = (w[0].frame as f64 * period, (w[1].frame + 1) as f64 * period);
                assert!(log.losses.iter().any(|&t| t >= a && t <= b), "{what}: left Track at frame {} with no loss logged", w[1].frame);
            }
        }

        // Recovered: reports in the last 20 frames, all within 3 px of the truth.
        let m = summarise(&log, &truth);
        let last: Vec<_> = log.frames[FRAMES - 20..].iter().collect();
        let tracked = last.iter().filter(|f| f.point.is_some()).count();
        fig.tracked_late += tracked;
        let late: Vec<_> = log.reports.iter().filter(|r| r.frame >= FRAMES - 20).collect();
        assert!(!late.is_empty(), "{what}: no report after the faults");
        let off = |r: &&coopwin_testbench::system::Report| {
            let t = truth[r.frame].corner;
            (f64::from(r.point.x) - t.0).hypot(f64::from(r.point.y) - t.1)
        };
        assert!(late.iter().all(|r| off(r) < 3.0), "{what}: off the truth after recovery: {:?}", late.iter().map(off).collect::<Vec<_>>());
        for &l in &log.losses {
            if let Some(r) = log.reports.iter().find(|r| r.t > l) {
                fig.recoveries.push((r.t - l) / period);
            }
        }

        // The robot link with one byte in 500 replaced: the decoder passes only what was sent.
        let sent: Vec<PositionUpdate> = decode(&log.robot_link).0;
        let vouched: Vec<_> = log.reports.iter().filter(|r| r.vouched).collect();
        assert_eq!(sent.len(), vouched.len(), "{what}: the clean link carries every report vouched for");
        for (u, r) in sent.iter().zip(vouched) {
            assert_eq!((u.x, u.y), (r.point.x, r.point.y), "{what}");
        }
        let mut bytes = log.robot_link.clone();
        let mut corrupted = 0;
        for b in bytes.iter_mut() {
            if rng.below(500) == 0 {
                *b ^= 1 + rng.below(255) as u8;
                corrupted += 1;
            }
        }
        let (got, _) = decode(&bytes);
        let mut i = 0;
        for u in &got {
            assert!(u.x.is_finite() && u.y.is_finite(), "{what}: a NaN passed the link");
            // In order, each accepted update is one that was sent.
            while i < sent.len() && sent[i] != *u {
                i += 1;
            }
            assert!(i < sent.len(), "{what}: the link passed an update that was never sent: {u:?}");
            i += 1;
        }
        assert!(sent.len() - got.len() <= 2 * corrupted, "{what}: {} updates lost to {corrupted} bad bytes", sent.len() - got.len());

        fig.frames += FRAMES;
        fig.dropped += log.dropped.len();
        fig.refused += log.refused.len();
        fig.watchdog += log.watchdog.len();
        fig.dark_frames += dark.len();
        fig.losses += log.losses.len();
        fig.link_bytes += bytes.len();
        fig.link_corrupted += corrupted;
        fig.link_sent += sent.len();
        fig.link_accepted += got.len();
        fig.rms.push(m.rms);
    }
    fig.recoveries.sort_by(f64::total_cmp);
    let n = fig.recoveries.len().max(1);
    eprintln!(
        "campaign: {} runs, {} frames; {} with random blanking, {} windows dropped, {} sets refused, {} watchdog rewrites, {} dark frames; {} losses logged, recovered in {:.1} frames on average (median {:.1}, max {:.1}); robot link: {} of {} bytes corrupted, {} of {} updates passed, none altered; RMS error per run {:.3}..{:.3} px",
        RUNS,
        fig.frames,
        fig.blanking_runs,
        fig.dropped,
        fig.refused,
        fig.watchdog,
        fig.dark_frames,
        fig.losses,
        fig.recoveries.iter().sum::<f64>() / n as f64,
        fig.recoveries.get(n / 2).copied().unwrap_or(0.0),
        fig.recoveries.last().copied().unwrap_or(0.0),
        fig.link_corrupted,
        fig.link_bytes,
        fig.link_accepted,
        fig.link_sent,
        fig.rms.iter().copied().fold(f64::INFINITY, f64::min),
        fig.rms.iter().copied().fold(0.0, f64::max),
    );
    eprintln!("frames tracked among the last 20 of each run: {} of {}", fig.tracked_late, 20 * RUNS);
    eprintln!("corrupted sets: {}, with a refusal or watchdog rewrite in the log: {}", fig.corrupted, fig.corrupted_logged);
    eprintln!("positions measured in dark frames: {:?}", fig.from_dark);
    assert!(fig.dropped > 0 && fig.refused + fig.watchdog > 0 && fig.dark_frames > 0 && fig.link_corrupted > 0, "every kind of fault was injected");
}

/// The position updates a byte stream carries (with the number of framing errors).
fn decode(bytes: &[u8]) -> (Vec<PositionUpdate>, usize) {
    let mut d = FrameDecoder::new();
    let (mut out, mut errors) = (Vec::new(), 0);
    for &b in bytes {
        match d.feed(b) {
            Some(Ok(p)) => match PositionUpdate::decode(&p) {
                Ok(u) => out.push(u),
                _ => errors += 1,
            },
            Some(Err(_)) => errors += 1,
            None => {}
        }
    }
    (out, errors)
}
