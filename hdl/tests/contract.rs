//! The window unit against the exported module's contract (`docs/window-logic.md`), driven
//! clock by clock with the direct-stepping driver. Reference: the software crop of each frame
//! (`Window::crop`), an independent model of what must be delivered.
use coopwin_hdl::ARM_MARGIN;
use coopwin_hdl::sim::camera::{CameraBus, RasterTiming, Window};
use coopwin_hdl::sim::run::{run_unit, Request};
use proptest::prelude::*;

const CA_D1: RasterTiming = RasterTiming::CA_D1;

/// Distinct pseudo-random frames, so a pixel from the wrong place or frame cannot match.
fn frames(n: usize, t: &RasterTiming, seed: u64) -> Vec<Vec<u8>> {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (0..n)
        .map(|_| {
            (0..t.width * t.height)
                .map(|_| {
                    s = s
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    (s >> 56) as u8
                })
                .collect()
        })
        .collect()
}

/// The software crop of a `width`-wide frame, as the unit's 16-bit output words.
fn crop(w: &Window, frame: &[u8], width: usize, decimate: bool) -> Vec<u16> {
    w.crop(frame, width, decimate).into_iter().map(u16::from).collect()
}

fn win(xmin: u32, xmax: u32, ymin: u32, ymax: u32) -> Window {
    Window {
        xmin,
        xmax,
        ymin,
        ymax,
    }
}

fn at(at: usize, window: Window, decimate: bool) -> Request {
    Request {
        at,
        window,
        decimate,
    }
}

#[test]
fn one_set_arms_exactly_one_frame() {
    let f = frames(4, &CA_D1, 1);
    let w = win(100, 123, 40, 63);
    let rec = run_unit::<8, 8>(&CA_D1, &f, &[at(500, w, false)]);
    let got = rec.delivered_per_frame(&CA_D1);
    // Written during frame 0 (fval rose at clock 0): it arms frame 1 only.
    assert!(got[0].is_empty());
    assert_eq!(got[1], crop(&w, &f[1], 256, false));
    assert!(got[2].is_empty() && got[3].is_empty());
}

#[test]
fn full_frame_and_corner_windows() {
    let f = frames(2, &CA_D1, 2);
    for w in [
        win(0, 255, 0, 255),
        win(0, 1, 0, 1),
        win(254, 255, 254, 255),
        win(0, 255, 255, 255),
    ] {
        if !w.is_valid() {
            continue;
        }
        let rec = run_unit::<8, 8>(&CA_D1, &f, &[at(10, w, false)]);
        let got = rec.delivered_per_frame(&CA_D1);
        assert_eq!(got[1], crop(&w, &f[1], 256, false), "{w:?}");
    }
}

#[test]
fn set_written_mid_window_does_not_disturb_it() {
    let f = frames(3, &CA_D1, 3);
    let w1 = win(10, 200, 10, 200);
    let w2 = win(50, 60, 70, 80);
    // w2 is written while frame 1 delivers w1 (line ~100 of frame 1).
    let mid = CA_D1.frame_clocks() + CA_D1.h_blank + 100 * CA_D1.line_clocks();
    let rec = run_unit::<8, 8>(&CA_D1, &f, &[at(10, w1, false), at(mid, w2, false)]);
    let got = rec.delivered_per_frame(&CA_D1);
    assert_eq!(got[1], crop(&w1, &f[1], 256, false));
    assert_eq!(got[2], crop(&w2, &f[2], 256, false));
}

#[test]
fn later_of_two_sets_wins() {
    let f = frames(3, &CA_D1, 4);
    let w1 = win(10, 20, 10, 20);
    let w2 = win(30, 45, 5, 9);
    let rec = run_unit::<8, 8>(&CA_D1, &f, &[at(10, w1, false), at(2000, w2, true)]);
    let got = rec.delivered_per_frame(&CA_D1);
    assert_eq!(got[1], crop(&w2, &f[1], 256, true));
    assert!(got[2].is_empty());
}

#[test]
fn invalid_set_is_refused_and_keeps_the_armed_one() {
    let f = frames(3, &CA_D1, 5);
    let good = win(10, 20, 30, 40);
    let bad = win(20, 20, 30, 40); // xmin == xmax
    let rec = run_unit::<8, 8>(&CA_D1, &f, &[at(10, good, false), at(3000, bad, false)]);
    let got = rec.delivered_per_frame(&CA_D1);
    assert_eq!(got[1], crop(&good, &f[1], 256, false));
    let bad_done = rec.completed[1];
    assert!(
        rec.outputs[bad_done + 2..].iter().all(|o| o.coord_error),
        "error held"
    );
    assert!(
        !rec.outputs[bad_done - 1].coord_error,
        "no error before the bad set"
    );
}

#[test]
fn error_clears_when_a_valid_set_completes() {
    let f = frames(2, &CA_D1, 6);
    let bad = win(5, 9, 9, 3);
    let good = win(1, 2, 3, 4);
    let rec = run_unit::<8, 8>(&CA_D1, &f, &[at(0, bad, false), at(40, good, false)]);
    let done = rec.completed[1];
    assert!(rec.outputs[rec.completed[0] + 2].coord_error);
    assert!(rec.outputs[done + 2..].iter().all(|o| !o.coord_error));
    assert_eq!(
        rec.delivered_per_frame(&CA_D1)[1],
        crop(&good, &f[1], 256, false)
    );
}

/// The arming margin, clock for clock: a set completed `ARM_MARGIN` clocks before frame 1's FVAL
/// is first sampled arms frame 1; one completed a clock later waits for frame 2, and leaves
/// frame 1 to the set already pending (it does not take it over).
#[test]
fn set_completed_arm_margin_before_fval_arms_that_frame_and_not_later() {
    let f = frames(3, &CA_D1, 7);
    let (pending, w) = (win(100, 120, 10, 20), win(3, 9, 0, 4));
    let probe = run_unit::<8, 8>(&CA_D1, &f[..1], &[at(100, w, false)]);
    let latency = probe.completed[0] - 100;
    let fval = CA_D1.frame_clocks(); // frame 1's FVAL is first sampled on this clock
    for late in [0, 1] {
        let start = fval - ARM_MARGIN - latency + late;
        let rec = run_unit::<8, 8>(&CA_D1, &f, &[at(1000, pending, false), at(start, w, false)]);
        assert_eq!(rec.completed[1] + ARM_MARGIN, fval + late);
        let got = rec.delivered_per_frame(&CA_D1);
        if late == 0 {
            assert_eq!(got[1], crop(&w, &f[1], 256, false), "the later set wins frame 1");
            assert!(got[2].is_empty());
        } else {
            assert_eq!(got[1], crop(&pending, &f[1], 256, false), "the pending set keeps frame 1");
            assert_eq!(got[2], crop(&w, &f[2], 256, false), "the late set arms frame 2");
        }
    }
}

/// LVAL high past FVAL's fall is no pixel: nothing is strobed once FVAL is low.
#[test]
fn nothing_is_strobed_after_fval_falls() {
    let t = RasterTiming { width: 32, height: 16, h_blank: 4, v_blank_lines: 1 };
    let f = frames(1, &t, 14);
    let (mut buses, starts) = gapped_run(&t, &f, 0, false);
    // Drop FVAL while the last line is still being sent: its last 5 pixels come after it.
    let last_line_end = buses[..starts[1]].iter().rposition(|b| b.lval && b.fval).unwrap();
    for b in &mut buses[last_line_end - 4..starts[1]] {
        b.fval = false;
    }
    let w = win(0, 31, 10, 15);
    let rec = coopwin_hdl::sim::run::run_bus::<5, 8>((32, 16), buses, &[at(0, w, false)], &[]);
    let whole: Vec<u16> = crop(&w, &f[0], 32, false);
    assert_eq!(strobed(&rec, starts[0], starts[1]), whole[..whole.len() - 5]);
}

#[test]
fn handshake_is_four_phase_and_answers_within_four_clocks() {
    let f = frames(1, &CA_D1, 8);
    let rec = run_unit::<8, 8>(&CA_D1, &f, &[at(5, win(1, 2, 3, 4), false)]);
    let mut rises = 0;
    for t in 1..rec.outputs.len() {
        let (strobe, ready) = (rec.inputs[t].port.strobe, rec.outputs[t].coord_ready);
        let was_ready = rec.outputs[t - 1].coord_ready;
        if ready && !was_ready {
            rises += 1;
            assert!(strobe, "CRDY1 rises only for an offered byte");
            let offered = (0..=t)
                .rev()
                .take_while(|&u| rec.inputs[u].port.strobe)
                .count();
            assert!(offered <= 4, "taken within 4 clocks");
        }
        if !ready && was_ready {
            assert!(!strobe, "CRDY1 falls only once CSTRB1 is low");
        }
    }
    assert_eq!(rises, 4);
}

#[test]
fn pixels_leave_within_four_clocks() {
    let f = frames(2, &CA_D1, 9);
    let w = win(7, 17, 2, 5);
    let rec = run_unit::<8, 8>(&CA_D1, &f, &[at(0, w, false)]);
    // Pair each strobe with the camera clocks of the window's pixels in frame 1, in order.
    let period = CA_D1.frame_clocks();
    let active = (period..2 * period).filter(|&t| rec.inputs[t].cam.fval && rec.inputs[t].cam.lval);
    let camera: Vec<usize> = active
        .enumerate()
        .filter(|(k, _)| (7..=17).contains(&(k % 256)) && (2..=5).contains(&(k / 256)))
        .map(|(_, t)| t)
        .collect();
    let strobes: Vec<usize> = (0..rec.outputs.len())
        .filter(|&t| rec.outputs[t].pixel_strobe)
        .collect();
    assert_eq!(camera.len(), strobes.len());
    for (c, s) in camera.iter().zip(&strobes) {
        assert!(s > c && s - c <= 4, "pixel at clock {c} strobed at {s}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Random windows, decimation and blanking: the strobed sequence is the software crop.
    #[test]
    fn strobes_equal_the_software_crop(
        x0 in 0u32..255, dx in 1u32..256, y0 in 0u32..255, dy in 1u32..256,
        decimate: bool, h_blank in 2usize..=64, v_blank in 1usize..=8, seed: u64,
    ) {
        let w = win(x0, (x0 + dx).min(255), y0, (y0 + dy).min(255));
        let t = RasterTiming { width: 256, height: 256, h_blank, v_blank_lines: v_blank };
        let f = frames(2, &t, seed);
        let rec = run_unit::<8, 8>(&t, &f, &[at(0, w, decimate)]);
        let got = rec.delivered_per_frame(&t);
        prop_assert!(got[0].is_empty());
        prop_assert_eq!(&got[1], &crop(&w, &f[1], 256, decimate));
    }
}

#[test]
fn writer_timing_is_what_the_unit_does() {
    // Hand count of one byte, from the clock the writer raises CSTRB1 (a): the unit registers
    // it on edge a, takes it and raises CRDY1 on a+1; the writer drops CSTRB1 for a+2, the
    // unit registers the low strobe on a+2 and drops CRDY1 on a+3; the writer offers the next
    // byte on a+4. So 4 clocks a byte, and the fourth byte (offered at 12) is taken on 13.
    let (latency, repeat) = coopwin_hdl::sim::run::writer_timing();
    assert_eq!(repeat, 16);
    assert_eq!(latency, 13);
}

/// The camera bus of `n` frames of `t` with `pixel_valid` gaps drawn from `seed` (none when
/// `gappy` is false), after 40 idle clocks, and where each frame starts.
fn gapped_run(t: &RasterTiming, images: &[Vec<u8>], seed: u64, gappy: bool) -> (Vec<CameraBus>, Vec<usize>) {
    let mut buses = vec![CameraBus { fval: false, lval: false, pixel: 0, pixel_valid: true }; 40];
    let mut starts = Vec::new();
    for (f, img) in images.iter().enumerate() {
        starts.push(buses.len());
        let gaps = |x: usize, y: usize| {
            let h = (seed ^ (f * 131 + y * t.width + x) as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 61;
            if gappy { [0, 0, 0, 0, 1, 1, 2, 5][h as usize] } else { 0 }
        };
        buses.extend(t.frame_with_gaps(|x, y| img[y * t.width + x], gaps));
    }
    starts.push(buses.len());
    (buses, starts)
}

/// The pixels strobed on clocks `from..to`.
fn strobed(rec: &coopwin_hdl::sim::run::Recording, from: usize, to: usize) -> Vec<u16> {
    rec.outputs[from..to].iter().filter(|o| o.pixel_strobe).map(|o| o.pixel_out).collect()
}

/// The silent failure: 640-pixel lines into the 256x256 unit. Its counters stop at
/// 255, so each line delivers the window's columns once (before: three times, wrapped).
#[test]
fn lines_longer_than_the_sensor_never_wrap_onto_the_window() {
    let t = RasterTiming { width: 640, height: 300, h_blank: 8, v_blank_lines: 2 };
    let f = frames(2, &t, 12);
    let w = win(10, 40, 250, 255);
    let (buses, starts) = gapped_run(&t, &f, 0, false);
    let rec = coopwin_hdl::sim::run::run_bus::<8, 8>((256, 256), buses, &[at(0, w, false)], &[]);
    let want: Vec<u16> = crop(&w, &f[0], 640, false);
    assert_eq!(want.len(), 31 * 6);
    assert_eq!(strobed(&rec, starts[0], starts[1]), want);
    assert!(strobed(&rec, starts[1], starts[2]).is_empty());
}

/// A reset in the middle of a window stops it; nothing is armed after it, `coord_error` is
/// low, and a set written after it arms the next frame.
#[test]
fn reset_mid_window_returns_to_power_on() {
    let t = RasterTiming { width: 64, height: 40, h_blank: 4, v_blank_lines: 2 };
    let f = frames(3, &t, 13);
    let (buses, starts) = gapped_run(&t, &f, 0, false);
    let (w1, w2) = (win(5, 60, 0, 39), win(1, 2, 1, 2));
    let reset_at = starts[0] + (starts[1] - starts[0]) / 2;
    let requests = [at(0, w1, false), at(reset_at - 200, win(3, 3, 0, 1), false), at(reset_at + 5, w2, true)];
    let rec = coopwin_hdl::sim::run::run_bus::<6, 8>((64, 40), buses, &requests, &[reset_at]);
    let whole: Vec<u16> = crop(&w1, &f[0], 64, false);
    let cut = strobed(&rec, starts[0], starts[1]);
    assert!(!cut.is_empty() && cut.len() < whole.len() && whole.starts_with(&cut));
    assert!(strobed(&rec, reset_at, starts[1]).is_empty());
    assert!(rec.outputs[reset_at - 1].coord_error, "the invalid set raised it");
    assert!(!rec.outputs[reset_at].coord_error, "the reset cleared it");
    let second: Vec<u16> = crop(&w2, &f[1], 64, true);
    assert_eq!(strobed(&rec, starts[1], starts[2]), second);
    assert!(strobed(&rec, starts[2], starts[3]).is_empty());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Any sensor size up to 64x64, lines and frames longer than the sensor, `pixel_valid`
    /// gaps: the strobed sequence is the software crop of the sensor's part of the frame.
    #[test]
    fn any_size_with_gaps_and_overlong_lines_strobes_the_crop(
        width in 16usize..=64, height in 16usize..=64, extra_x in 0usize..8, extra_y in 0usize..3,
        fx0 in 0.0..1.0f64, fx1 in 0.0..1.0f64, fy0 in 0.0..1.0f64, fy1 in 0.0..1.0f64,
        decimate: bool, gappy: bool, seed: u64,
    ) {
        let t = RasterTiming { width: width + extra_x, height: height + extra_y, h_blank: 3, v_blank_lines: 1 };
        let span = |a: f64, b: f64, n: usize| {
            let (lo, hi) = ((a * (n - 1) as f64) as u32, (b * (n - 1) as f64) as u32);
            (lo.min(hi).min(n as u32 - 2), hi.max(lo + 1).max(lo.min(hi) + 1).min(n as u32 - 1))
        };
        let ((x0, x1), (y0, y1)) = (span(fx0, fx1, width), span(fy0, fy1, height));
        let w = win(x0, x1, y0, y1);
        let f = frames(2, &t, seed);
        let (buses, starts) = gapped_run(&t, &f, seed, gappy);
        let rec = coopwin_hdl::sim::run::run_bus::<6, 8>((width, height), buses, &[at(0, w, decimate)], &[]);
        let want: Vec<u16> = crop(&w, &f[0], t.width, decimate);
        prop_assert_eq!(strobed(&rec, starts[0], starts[1]), want);
        prop_assert!(strobed(&rec, starts[1], starts[2]).is_empty());
    }

    /// A 300-column sensor takes two bytes a coordinate: any window inside it is delivered,
    /// and a set reaching column 300 or row 20 is refused with `coord_error`.
    #[test]
    fn two_byte_coordinates_reach_every_column_and_stop_at_the_edge(
        x0 in 0u32..299, dx in 1u32..300, y0 in 0u32..19, dy in 1u32..20, past_edge: bool,
    ) {
        let t = RasterTiming { width: 300, height: 20, h_blank: 4, v_blank_lines: 1 };
        let f = frames(2, &t, u64::from(x0));
        let (buses, starts) = gapped_run(&t, &f, 0, false);
        let w = if past_edge { win(x0, x0 + dx.max(300 - x0), y0, y0 + dy) } else { win(x0, (x0 + dx).min(299), y0, (y0 + dy).min(19)) };
        let rec = coopwin_hdl::sim::run::run_bus::<9, 8>((300, 20), buses, &[at(0, w, false)], &[]);
        prop_assert_eq!(rec.completed.len(), 1, "one 8-byte set");
        let refused = w.xmax >= 300 || w.ymax >= 20;
        let want: Vec<u16> = if refused { Vec::new() } else { crop(&w, &f[0], 300, false) };
        prop_assert_eq!(strobed(&rec, starts[0], starts[2]), want);
        prop_assert_eq!(rec.outputs[starts[0]].coord_error, refused);
    }
}
