//! The corner detector on rendered polygons with exactly known corners (thesis ch. 3):
//! each Q3 case, Q1/Q2/Q3 results and the Golden Section Search case, several
//! orientations, with and without clutter and noise, with asserted error bounds; the
//! default line fit on the same scenes within 0.3 px.
//!
//! Rendering: pixel `(i, j)` covers `[i-0.5, i+0.5) x [j-0.5, j+0.5)` (so a pixel's
//! index is its centre), coverage by 8x8 supersampling, then a 3x3 box blur (the optics
//! of a real camera; it also makes edge bands 3-4 px wide, which the plus-shaped
//! opening needs to keep them).
#[path = "support/optics.rs"]
mod optics;

use coopwin_firmware::kernels::corner::{CornerCase, CornerDetector, CornerParams, NoCorner};
use coopwin_firmware::kernels::view::WindowView;

type P = (f64, f64);

/// Inside the convex polygon `poly` (counter-clockwise in image coordinates, y down,
/// i.e. clockwise on screen): all cross products non-negative.
fn inside(poly: &[P], x: f64, y: f64) -> bool {
    (0..poly.len()).all(|i| {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0) >= 0.0
    })
}

/// Deterministic noise in [-amp, amp] (xorshift).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

struct Scene {
    size: usize,
    poly: Vec<P>,
    noise: f64,
    clutter: bool,
}

fn render(s: &Scene) -> Vec<u8> {
    let n = s.size;
    let (bg, fg) = (60.0, 180.0);
    let mut cov = vec![0f64; n * n];
    for j in 0..n {
        for i in 0..n {
            let mut c = 0;
            for sj in 0..8 {
                for si in 0..8 {
                    let x = i as f64 - 0.5 + (si as f64 + 0.5) / 8.0;
                    let y = j as f64 - 0.5 + (sj as f64 + 0.5) / 8.0;
                    c += usize::from(inside(&s.poly, x, y));
                }
            }
            cov[j * n + i] = bg + (fg - bg) * c as f64 / 64.0;
        }
    }
    if s.clutter {
        // Bright 2x2 specks wherever they stay at least 8 px from the object's boundary
        // (isolated clutter, which the labelling must remove), at most four of them.
        let near_edge = |x: f64, y: f64| {
            (0..s.poly.len()).any(|i| {
                let (a, b) = (s.poly[i], s.poly[(i + 1) % s.poly.len()]);
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let t = (((x - a.0) * dx + (y - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
                (a.0 + t * dx - x).hypot(a.1 + t * dy - y) < 8.0
            })
        };
        let spots = [(2usize, 2usize), (n - 4, 2), (2, n - 4), (n - 4, n - 4), (n / 2, 2), (2, n / 2), (n - 4, n / 2), (n / 2, n - 4)];
        for &(x, y) in spots.iter().filter(|&&(x, y)| !near_edge(x as f64 + 0.5, y as f64 + 0.5)).take(4) {
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                cov[(y + dy) * n + x + dx] = 250.0;
            }
        }
    }
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ (n as u64) ^ s.poly.len() as u64);
    optics::blur_and_quantise(&cov, n, || s.noise * (2.0 * rng.next() - 1.0))
}

/// A wedge with apex `c` and its two edges leaving in directions `a1`, `a2` (degrees,
/// image coordinates: 0 = +x, 90 = +y down); the object is the region between them
/// (going from a1 to a2 the short way), made big enough to leave the window.
fn wedge(c: P, a1: f64, a2: f64) -> Vec<P> {
    let far = 200.0;
    let d = |a: f64| (c.0 + far * a.to_radians().cos(), c.1 + far * a.to_radians().sin());
    let mid = (a1 + a2) / 2.0;
    // Apex, then the far points in angular order: the polygon is convex for angles < 180°.
    vec![c, d(a1), d(mid), d(a2)]
}

/// Which rule located the corner, without Q3's source.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Q1,
    Q2,
    Q3,
    Lines,
    Any,
}

fn kind(c: CornerCase) -> Kind {
    match c {
        CornerCase::Q1(_) => Kind::Q1,
        CornerCase::Q2(_) => Kind::Q2,
        CornerCase::Q3(_) => Kind::Q3,
        CornerCase::Gss => Kind::Any,
        CornerCase::Lines => Kind::Lines,
    }
}

/// The thesis' rules with the band-width tolerance (no line fit).
const RULES: CornerParams = CornerParams { threshold: 50, distinct_tol: 2, refine: false };

/// The default detector (line fit) must be within `LINES_BOUND` px; the thesis' rules
/// must take the `want` case and be within `bound` px.
const LINES_BOUND: f64 = 0.3;

fn check(name: &str, size: usize, c: P, a1: f64, a2: f64, want: Kind, bound: f64) {
    let mut det = Box::new(CornerDetector::new());
    for (noise, clutter) in [(0.0, false), (4.0, false), (0.0, true), (4.0, true)] {
        let scene = Scene { size, poly: wedge(c, a1, a2), noise, clutter };
        let img = render(&scene);
        let v = WindowView::packed(&img, size, size).unwrap();
        for (mode, params, want, bound) in [("rules", RULES, want, bound), ("lines", CornerParams::new(50), Kind::Lines, LINES_BOUND)] {
            let r = det.detect(&v, &params);
            let corner = r.unwrap_or_else(|e| panic!("{name} {mode} noise {noise} clutter {clutter}: {e:?}"));
            let err = ((corner.x as f64 - c.0).powi(2) + (corner.y as f64 - c.1).powi(2)).sqrt();
            eprintln!("{name:28} {mode} noise {noise} clutter {clutter:5}: {:?} at ({}, {}) err {err:.2}", corner.case, corner.x, corner.y);
            if want != Kind::Any {
                assert_eq!(kind(corner.case), want, "{name} {mode} noise {noise} clutter {clutter}: {:?}", corner.case);
            }
            assert!(err <= bound, "{name} {mode} noise {noise} clutter {clutter}: error {err:.2} > {bound}");
        }
    }
}

#[test]
fn q3_bar_p00_tip_up() {
    // Apex up, edges down-left and down-right; three rotations.
    for (i, rot) in [-15.0, 0.0, 15.0].into_iter().enumerate() {
        // The rules give the band's top pixel, up to 1.6 px from the apex.
        check(&format!("tip up rot {rot}"), 24, (11.3, 6.6 + i as f64 * 0.3), 45.0 + rot, 135.0 + rot, Kind::Q3, 2.0);
    }
}

#[test]
fn q1_tip_left() {
    for rot in [-10.0, 0.0, 10.0] {
        check(&format!("tip left rot {rot}"), 24, (6.4, 11.7), -40.0 + rot, 40.0 + rot, Kind::Q1, 1.5);
    }
}

#[test]
fn q2_tip_right() {
    for rot in [-10.0, 0.0, 10.0] {
        check(&format!("tip right rot {rot}"), 24, (16.6, 11.2), 140.0 + rot, 220.0 + rot, Kind::Q2, 1.5);
    }
}

#[test]
fn q3_bar_p10_tip_down() {
    for rot in [-10.0, 0.0, 10.0] {
        // Looser bound for the rules: Q3 = P̄10 is the *first* (leftmost) pixel of the
        // flat bottom run of the band around the tip, up to 2.7 px from the tip when it
        // is rotated.
        check(&format!("tip down rot {rot}"), 20, (9.6, 14.4), 225.0 + rot, 315.0 + rot, Kind::Q3, 3.0);
    }
}

#[test]
fn right_angle_part_corner() {
    // The thesis' metal part: a 90° corner, object to the lower right, small rotations.
    for rot in [0.0, 8.0, -8.0] {
        check(&format!("part corner rot {rot}"), 20, (8.3, 9.1), 0.0 + rot, 90.0 + rot, Kind::Any, 1.5);
    }
}

#[test]
fn straight_edges_are_not_corners() {
    let mut det = Box::new(CornerDetector::new());
    for (name, poly, want) in [
        ("vertical", vec![(10.2, -50.0), (80.0, -50.0), (80.0, 80.0), (10.2, 80.0)], NoCorner::VerticalLine),
        ("horizontal", vec![(-50.0, 80.0), (-50.0, 9.7), (80.0, 9.7), (80.0, 80.0)], NoCorner::HorizontalLine),
    ] {
        let img = render(&Scene { size: 24, poly, noise: 0.0, clutter: false });
        let v = WindowView::packed(&img, 24, 24).unwrap();
        assert_eq!(det.detect(&v, &RULES).err(), Some(want), "{name}");
        // The line fit finds one edge orientation only.
        assert_eq!(det.detect(&v, &CornerParams::new(50)).err(), Some(NoCorner::StraightLine), "{name}");
    }
    let flat = vec![100u8; 24 * 24];
    let v = WindowView::packed(&flat, 24, 24).unwrap();
    assert_eq!(det.detect(&v, &CornerParams::new(50)).err(), Some(NoCorner::NoEdges));
}
