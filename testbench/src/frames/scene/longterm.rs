//! Long-term sets (issue 38): the target among look-alikes, behind occluders and out of the
//! view, composited from the bundled photographs with exact ground truth, including whether
//! the target can be seen at all.
//!
//! Every actor is a textured rectangle moved in exact sub-pixel translation: its pixels are
//! the photo sampled bilinearly, blended with what lies under it by the share of each pixel it
//! covers. The target is a 48x48 cut of the object photo (`fixtures/real/object.png`, wood
//! grain); its look-alikes are the same cut mirrored, turned half round or flipped (the same
//! kind of object: the grain runs the same way when turned, the other way when mirrored), or
//! the same cut again (an identical copy); occluders are panels of the background photo (the
//! cat), brightened so they stand out of the dim background. Layers are drawn back to front:
//! actors behind the target, the target, actors in front of it.
//!
//! A frame's truth says where the target's centre is and whether it is
//! [`Presence::Visible`] (at least half of it in the view and uncovered),
//! [`Presence::Hidden`] (in the view, more than half covered) or [`Presence::Gone`] (more
//! than half of it out of the view), as VOT-LT and OxUvA label a target present or absent.
use super::rng::Rng;
use super::texture::{Photo, BACKGROUND_PHOTO, PART_PHOTO};
use crate::frames::{FrameError, FrameSource};

/// Frame size of every set.
pub const WIDTH: usize = 320;
/// Frame height of every set.
pub const HEIGHT: usize = 240;
/// Frames per set.
pub const FRAMES: usize = 300;
/// Frame rate: a video camera's.
pub const FPS: f64 = 30.0;
/// Side of the target and of its look-alikes, in pixels.
pub const SIDE: f64 = 48.0;
/// Camera noise, gray levels (standard deviation).
const NOISE: f64 = 2.0;
/// Gain on the background photo where it makes an occluding panel (the photo is exposed at
/// 0.6 to make a dim background; a panel is lit as the cat was).
const PANEL_GAIN: f64 = 1.6;

/// Whether the target can be seen in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Presence {
    /// At least half of the target is in the view and uncovered.
    Visible,
    /// In the view, but more than half of it is covered.
    Hidden,
    /// More than half of it is out of the view.
    Gone,
}

impl Presence {
    /// `visible`, `hidden` or `gone`, as the ground-truth files spell it.
    pub fn name(self) -> &'static str {
        match self {
            Presence::Visible => "visible",
            Presence::Hidden => "hidden",
            Presence::Gone => "gone",
        }
    }
}

/// The target in one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Presenced {
    /// The target's centre (pixel centres at integers).
    pub centre: (f64, f64),
    /// Whether it can be seen.
    pub presence: Presence,
    /// The share of the target in the view and uncovered (0-1).
    pub seen: f64,
}

/// How a look-alike's surface is the target's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Look {
    /// The target's own cut: an identical copy.
    Same,
    /// Mirrored left to right.
    Mirrored,
    /// Turned half round.
    Turned,
    /// Upside down.
    Flipped,
}

/// What an actor's pixels are.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Surface {
    /// The object photo's central 48x48, as `Look` makes it.
    Object(Look),
    /// The background photo from this offset, brightened: an occluding panel.
    Panel(f64, f64),
}

/// Whether an actor passes behind or in front of the target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Layer {
    Behind,
    Front,
}

/// A textured rectangle on a path: `keys` are `(frame, x, y)` of its centre, linear between
/// them and held before the first and after the last; it is in the scene over `during`.
#[derive(Clone, Debug)]
struct Actor {
    surface: Surface,
    size: (f64, f64),
    keys: Vec<(f64, f64, f64)>,
    layer: Layer,
    during: (usize, usize),
}

impl Actor {
    fn object(look: Look, layer: Layer, keys: &[(f64, f64, f64)]) -> Actor {
        Actor { surface: Surface::Object(look), size: (SIDE, SIDE), keys: keys.to_vec(), layer, during: (0, FRAMES) }
    }

    fn panel(offset: (f64, f64), size: (f64, f64), centre: (f64, f64), during: (usize, usize)) -> Actor {
        Actor { surface: Surface::Panel(offset.0, offset.1), size, keys: vec![(0.0, centre.0, centre.1)], layer: Layer::Front, during }
    }

    /// The centre at frame `k`.
    fn at(&self, k: usize) -> (f64, f64) {
        let t = k as f64;
        let (first, last) = (self.keys[0], self.keys[self.keys.len() - 1]);
        if t <= first.0 {
            return (first.1, first.2);
        }
        for w in self.keys.windows(2) {
            let (a, b) = (w[0], w[1]);
            if t <= b.0 {
                let u = (t - a.0) / (b.0 - a.0).max(f64::EPSILON);
                return (a.1 + u * (b.1 - a.1), a.2 + u * (b.2 - a.2));
            }
        }
        (last.1, last.2)
    }

    fn present(&self, k: usize) -> bool {
        (self.during.0..self.during.1).contains(&k)
    }
}

/// One long-term set: a name, what it tests, and its actors.
#[derive(Clone, Debug)]
pub struct LongTermSet {
    /// The set's name (`lookalike-front`, ...).
    pub name: &'static str,
    /// What happens in it, one line.
    pub about: &'static str,
    target: Actor,
    others: Vec<Actor>,
    seed: u64,
}

/// A target swinging left and right across the view's middle, once a run: at most 1.47 px a
/// frame, inside the thesis's +-2 px Foveal search at 30 frames/s.
fn swing(amplitude: f64, y: f64) -> Vec<(f64, f64, f64)> {
    (0..=60).map(|i| {
        let k = i as f64 * FRAMES as f64 / 60.0;
        (k, WIDTH as f64 / 2.0 - 0.5 + amplitude * (std::f64::consts::TAU * k / FRAMES as f64).sin(), y)
    }).collect()
}

/// A look-alike crossing the view from one side to the other and back, in front of or behind
/// a target on [`swing`].
fn crossing(look: Look, layer: Layer) -> Actor {
    let (l, r) = (-SIDE, WIDTH as f64 + SIDE);
    Actor::object(look, layer, &[(40.0, r, 122.0), (140.0, l, 122.0), (170.0, l, 116.0), (270.0, r, 116.0)])
}

/// The sets.
pub fn sets() -> Vec<LongTermSet> {
    let (w, h) = (WIDTH as f64, HEIGHT as f64);
    let swinging = || Actor::object(Look::Same, Layer::Behind, &swing(70.0, 119.5));
    let set = |name, about, target, others, seed| LongTermSet { name, about, target, others, seed };
    // The target leaves by the right edge; three look-alikes come in, the last one `third`.
    let leaving = |name, about, third, seed| {
        LongTermSet {
            name,
            about,
            target: Actor::object(Look::Same, Layer::Behind, &[(0.0, 180.5, 110.5), (20.0, 190.0, 112.0), (150.0, w + SIDE, 130.0)]),
            others: vec![
                Actor::object(Look::Turned, Layer::Front, &[(160.0, -SIDE, 100.0), (220.0, 150.0, 110.0), (300.0, 200.0, 150.0)]),
                Actor::object(Look::Mirrored, Layer::Front, &[(180.0, w + SIDE, 150.0), (260.0, 130.0, 120.0), (300.0, 100.0, 110.0)]),
                Actor::object(third, Layer::Front, &[(200.0, 160.0, h + SIDE), (280.0, 120.0, 115.0)]),
            ],
            seed,
        }
    };
    vec![
        set("lookalike-front", "a mirrored look-alike crosses in front of the target, twice", swinging(), vec![crossing(Look::Mirrored, Layer::Front)], 1),
        set("lookalike-behind", "a mirrored look-alike passes behind the target, twice", swinging(), vec![crossing(Look::Mirrored, Layer::Behind)], 2),
        set("turned-front", "a look-alike turned half round (its grain runs as the target's) crosses in front, twice", swinging(), vec![crossing(Look::Turned, Layer::Front)], 3),
        set("identical-behind", "an identical copy passes behind the target, twice", swinging(), vec![crossing(Look::Same, Layer::Behind)], 4),
        leaving("leaves", "the target leaves the view for good near frame 130; look-alikes come in from frame 160", Look::Flipped, 5),
        leaving(
            "leaves-identical",
            "as leaves, but the third newcomer is an identical copy: nothing in its look tells it from the target",
            Look::Same,
            10,
        ),
        set(
            "crowd",
            "four look-alikes walk through the target's place, each passing in front of it",
            Actor::object(Look::Same, Layer::Behind, &[(0.0, 150.5, 120.5), (100.0, 175.0, 110.0), (200.0, 150.0, 130.0), (300.0, 170.0, 120.0)]),
            vec![
                Actor::object(Look::Turned, Layer::Front, &[(20.0, -SIDE, 80.0), (120.0, w + SIDE, 160.0)]),
                Actor::object(Look::Mirrored, Layer::Front, &[(70.0, 160.0, h + SIDE), (170.0, 165.0, -SIDE)]),
                Actor::object(Look::Flipped, Layer::Front, &[(140.0, w + SIDE, 90.0), (240.0, -SIDE, 150.0)]),
                Actor::object(Look::Turned, Layer::Front, &[(190.0, 120.0, -SIDE), (290.0, 200.0, h + SIDE)]),
            ],
            6,
        ),
        set(
            "panel",
            "the target passes behind a textured panel for 49 frames and comes out 70 px further on",
            Actor::object(Look::Same, Layer::Behind, &[(0.0, 40.5, 120.5), (40.0, 60.0, 120.0), (180.0, 260.0, 120.0), (300.0, 280.0, 125.0)]),
            vec![Actor::panel((60.0, 20.0), (70.0, h), (160.0, 119.5), (0, FRAMES))],
            7,
        ),
        set(
            "partial",
            "the target stops; a textured panel covers its left third for 20 frames",
            Actor::object(Look::Same, Layer::Behind, &[(0.0, 100.5, 120.5), (120.0, 160.0, 120.0), (180.0, 160.0, 120.0), (300.0, 220.0, 110.0)]),
            vec![Actor::panel((20.0, 120.0), (40.0, 60.0), (160.0 - SIDE / 2.0 + 16.0 - 20.0, 120.0), (140, 160))],
            8,
        ),
        set(
            "clutter",
            "look-alike patches lie still beside the target's path, 10-20 px from it",
            Actor::object(Look::Same, Layer::Behind, &[(0.0, 80.5, 80.5), (120.0, 240.0, 80.0), (210.0, 160.0, 170.0), (300.0, 80.0, 80.0)]),
            vec![
                Actor::object(Look::Turned, Layer::Behind, &[(0.0, 160.0, 80.0 - SIDE - 12.0)]),
                Actor::object(Look::Mirrored, Layer::Behind, &[(0.0, 240.0 + SIDE + 14.0, 90.0)]),
                Actor::object(Look::Flipped, Layer::Behind, &[(0.0, 200.0 + SIDE / 2.0 + 16.0, 125.0 - SIDE / 2.0 + 4.0)]),
                Actor::object(Look::Turned, Layer::Behind, &[(0.0, 120.0 - SIDE / 2.0 - 14.0, 125.0 + SIDE / 2.0)]),
            ],
            9,
        ),
    ]
}

/// The photos the sets are made of.
struct Photos {
    object: Photo,
    background: Photo,
}

impl Photos {
    fn new() -> Photos {
        Photos { object: Photo::decode(PART_PHOTO), background: Photo::decode(BACKGROUND_PHOTO) }
    }

    /// An actor's surface at `(u, v)` from its top-left pixel centre.
    fn sample(&self, s: Surface, (u, v): (f64, f64)) -> f64 {
        let n = SIDE - 1.0;
        // The 48x48 cut's origin in the 64x64 object photo.
        let o = 8.0;
        match s {
            Surface::Object(look) => {
                let (u, v) = match look {
                    Look::Same => (u, v),
                    Look::Mirrored => (n - u, v),
                    Look::Turned => (n - u, n - v),
                    Look::Flipped => (u, n - v),
                };
                self.object.bilinear(u + o, v + o)
            }
            Surface::Panel(x, y) => (PANEL_GAIN * self.background.bilinear(u + x, v + y)).min(255.0),
        }
    }
}

/// The share of pixel `x` (covering `x - 0.5..x + 0.5`) inside `lo..lo + len`.
fn overlap(x: f64, lo: f64, len: f64) -> f64 {
    ((x + 0.5).min(lo + len) - (x - 0.5).max(lo)).clamp(0.0, 1.0)
}

/// Draws `a` at frame `k` over `img`, multiplying `under` (the share of each pixel the target
/// still shows, when given) by what it leaves uncovered.
fn draw(img: &mut [f64], under: Option<&mut [f64]>, a: &Actor, k: usize, photos: &Photos) {
    if !a.present(k) {
        return;
    }
    let (cx, cy) = a.at(k);
    let (sw, sh) = a.size;
    let (left, top) = (cx - (sw - 1.0) / 2.0 - 0.5, cy - (sh - 1.0) / 2.0 - 0.5);
    let range = |lo: f64, len: f64, n: usize| (lo.floor().max(0.0) as usize).min(n)..((lo + len).ceil().max(0.0) as usize + 1).min(n);
    let mut under = under;
    for y in range(top, sh, HEIGHT) {
        let cov_y = overlap(y as f64, top, sh);
        for x in range(left, sw, WIDTH) {
            let cov = overlap(x as f64, left, sw) * cov_y;
            if cov <= 0.0 {
                continue;
            }
            let uv = ((x as f64 - left - 0.5).clamp(0.0, sw - 1.0), (y as f64 - top - 0.5).clamp(0.0, sh - 1.0));
            let i = y * WIDTH + x;
            img[i] = cov * photos.sample(a.surface, uv) + (1.0 - cov) * img[i];
            if let Some(u) = under.as_deref_mut() {
                u[i] *= 1.0 - cov;
            }
        }
    }
}

impl LongTermSet {
    /// Renders frame `k` as 8-bit gray, with the target's truth.
    fn render(&self, k: usize, photos: &Photos) -> (Vec<u8>, Presenced) {
        let mut img: Vec<f64> = (0..WIDTH * HEIGHT).map(|i| photos.background.mirrored((i % WIDTH) as i64, (i / WIDTH) as i64)).collect();
        for a in self.others.iter().filter(|a| a.layer == Layer::Behind) {
            draw(&mut img, None, a, k, photos);
        }
        // The target's coverage, then what the actors in front leave of it.
        let mut blank = vec![0.0; WIDTH * HEIGHT];
        let mut shown = vec![1.0; WIDTH * HEIGHT];
        draw(&mut blank, Some(&mut shown), &self.target, k, photos);
        let mut target_cov: Vec<f64> = shown.iter().map(|s| 1.0 - s).collect();
        draw(&mut img, None, &self.target, k, photos);
        for a in self.others.iter().filter(|a| a.layer == Layer::Front) {
            draw(&mut img, Some(&mut target_cov), a, k, photos);
        }
        let (cx, cy) = self.target.at(k);
        let area = self.target.size.0 * self.target.size.1;
        let out_of_view = (1.0 - shown.iter().map(|s| 1.0 - s).sum::<f64>() / area).max(0.0);
        let seen = target_cov.iter().sum::<f64>() / area;
        let presence = if out_of_view > 0.5 {
            Presence::Gone
        } else if seen < 0.5 {
            Presence::Hidden
        } else {
            Presence::Visible
        };
        let mut rng = Rng::new(self.seed.wrapping_mul(1_000_003).wrapping_add(k as u64));
        let pixels = img.iter().map(|&v| (v + NOISE * rng.normal()).round().clamp(0.0, 255.0) as u8).collect();
        (pixels, Presenced { centre: (cx, cy), presence, seen })
    }

    /// The target's box on frame 0 as OpenCV's `x,y,w,h` (columns `x..x+w-1`); every set
    /// starts the target's centre where a whole-pixel box centres on it.
    pub fn start_box(&self) -> (u32, u32, u32, u32) {
        let (cx, cy) = self.target.at(0);
        let (w, h) = self.target.size;
        ((cx - (w - 1.0) / 2.0).round() as u32, (cy - (h - 1.0) / 2.0).round() as u32, w as u32, h as u32)
    }

    /// Every frame rendered, with its truth.
    pub fn render_all(&self) -> LongTermFrames {
        let photos = Photos::new();
        let (frames, truth) = (0..FRAMES).map(|k| self.render(k, &photos)).unzip();
        LongTermFrames { frames, truth }
    }
}

/// A set's frames, rendered once, and the target's truth in each.
pub struct LongTermFrames {
    frames: Vec<Vec<u8>>,
    /// The target in every frame.
    pub truth: Vec<Presenced>,
}

impl LongTermFrames {
    /// Frame `k`'s pixels.
    pub fn pixels(&self, k: usize) -> Option<&[u8]> {
        self.frames.get(k).map(Vec::as_slice)
    }

    /// A fingerprint of every frame's pixels ([`crate::frames::frames_fingerprint`]).
    pub fn fingerprint(&self) -> String {
        crate::frames::frames_fingerprint(self.frames.iter().map(Vec::as_slice))
    }
}

impl FrameSource for LongTermFrames {
    fn size(&self) -> (usize, usize) {
        (WIDTH, HEIGHT)
    }
    fn len(&self) -> usize {
        self.frames.len()
    }
    fn frame(&mut self, k: usize) -> Result<&[u8], FrameError> {
        self.frames.get(k).map(Vec::as_slice).ok_or(FrameError::Missing(k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(name: &str) -> LongTermSet {
        sets().into_iter().find(|s| s.name == name).unwrap()
    }

    #[test]
    fn every_set_starts_on_a_box_centred_on_the_target() {
        for s in sets() {
            let (x, y, w, h) = s.start_box();
            let centre = (f64::from(x) + (f64::from(w) - 1.0) / 2.0, f64::from(y) + (f64::from(h) - 1.0) / 2.0);
            assert_eq!(centre, s.target.at(0), "{}", s.name);
        }
    }

    #[test]
    fn a_still_target_is_the_photo_cut_where_the_truth_puts_it() {
        // Hand reference: with its centre on a pixel centre plus 0.5 the target covers whole
        // pixels, so each pixel under it is the photo's own (up to the noise, sigma 2).
        let photos = Photos::new();
        let s = LongTermSet { name: "t", about: "", target: Actor::object(Look::Same, Layer::Behind, &[(0.0, 100.5, 80.5)]), others: vec![], seed: 1 };
        let (img, t) = s.render(0, &photos);
        assert_eq!((t.centre, t.presence), ((100.5, 80.5), Presence::Visible));
        assert!((t.seen - 1.0).abs() < 1e-9);
        // Top-left pixel of the target: column 100.5 - 23.5 = 77, row 57; the photo's (8, 8).
        let mut err = 0.0;
        for (dy, dx) in [(0, 0), (10, 20), (47, 47)] {
            let want = photos.object.mirrored(8 + dx, 8 + dy);
            err += (f64::from(img[(57 + dy as usize) * WIDTH + 77 + dx as usize]) - want).abs();
        }
        assert!(err < 3.0 * 8.0, "{err}");
    }

    #[test]
    fn the_truth_says_hidden_and_gone_where_the_geometry_does() {
        // Panel: 70 px wide at x 125..195 (centre 160, hand reference); the target, 48 wide,
        // is more than half covered while its centre is over the panel (a pixel's margin at
        // its edges, where exactly half is).
        let panel = set("panel").render_all();
        let states: Vec<Presence> = panel.truth.iter().map(|t| t.presence).collect();
        for (k, t) in panel.truth.iter().enumerate() {
            let x = t.centre.0;
            if (x - 125.0).abs() > 1.0 && (x - 195.0).abs() > 1.0 {
                assert_eq!(t.presence == Presence::Hidden, (125.0..195.0).contains(&x), "frame {k}: {t:?}");
            }
        }
        let hidden = states.iter().filter(|p| **p == Presence::Hidden).count();
        // 70 px at 200 px / 140 frames: 49 frames.
        assert!((48..=50).contains(&hidden), "{hidden}");
        // Leaves: its centre crosses the right edge (x 319.5) on its way to 368 by frame 150.
        let leaves = set("leaves").render_all();
        let gone = leaves.truth.iter().position(|t| t.presence == Presence::Gone).unwrap();
        assert!(leaves.truth[gone].centre.0 > 319.5 && leaves.truth[gone - 1].centre.0 <= 319.5 + 1.0, "{:?}", leaves.truth[gone]);
        assert!(leaves.truth[gone..].iter().all(|t| t.presence == Presence::Gone));
    }

    #[test]
    fn a_look_alike_in_front_hides_the_target_only_while_it_covers_most_of_it() {
        let f = set("lookalike-front").render_all();
        let hidden: Vec<usize> = (0..FRAMES).filter(|&k| f.truth[k].presence == Presence::Hidden).collect();
        assert!(!hidden.is_empty() && hidden.len() < 40, "{hidden:?}");
        let behind = set("lookalike-behind").render_all();
        assert!(behind.truth.iter().all(|t| t.presence == Presence::Visible));
    }
}
