//! `coopwin scene`: writes a synthetic scene's frames as 8-bit PNG and its ground truth
//! (`groundtruth.csv`), the input of `coopwin track`.
use super::args;
use super::output::{check_folder, create_folder, OutFile};
use super::{io_error, CliError};
use crate::experiments::{appearance, real_images};
use crate::frames::groundtruth::{self, Truth};
use crate::frames::scene::longterm::{self, Presence};
use std::fmt::Write as _;
use crate::frames::scene::{PathKind, Scene, SceneConfig};
use std::path::{Path, PathBuf};

/// `--path`.
#[derive(Clone, Copy, clap::ValueEnum)]
// No doc comments on the variants: clap would list them as help beside each value.
#[allow(missing_docs)]
pub enum PathArg {
    Pendulum,
    Triangle,
    Swing,
}

/// `--lighting`.
#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
// No doc comments on the variants: clap would list them as help beside each value.
#[allow(missing_docs)]
pub enum LightingArg {
    Constant,
    Ramp,
}

/// `coopwin scene`'s options.
#[derive(clap::Args)]
pub struct SceneArgs {
    /// The target's path: pendulum (Fig. 2.8), triangle (Fig. 3.4), or a swing inside the view
    #[arg(long, value_enum, default_value_t = PathArg::Triangle)]
    pub path: PathArg,
    /// Target speed in pixels per second
    #[arg(long, default_value_t = 100.0)]
    pub speed: f64,
    /// Number of frames (at 114 frames/s)
    #[arg(long, default_value_t = 300)]
    pub frames: usize,
    /// Lighting: constant, or a ~25% brightening over the middle third (Fig. 4.2)
    #[arg(long, value_enum, default_value_t = LightingArg::Constant)]
    pub lighting: LightingArg,
    /// Static clutter on the background
    #[arg(long)]
    pub clutter: bool,
    /// A bar occluding the path for a tenth of the run
    #[arg(long)]
    pub occlusion: bool,
    /// Gaussian noise standard deviation in gray levels
    #[arg(long, default_value_t = 0.0)]
    pub noise: f64,
    /// Random seed (texture, clutter, noise)
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Real photographs (fixtures/real/) for the part's surface and the background
    #[arg(long)]
    pub photo: bool,
    /// Frame size WxH, each side 64..4096 (the path scales with it)
    #[arg(long, value_name = "WxH", default_value = "256x256", value_parser = args::parse_size)]
    pub size: (usize, usize),
    /// Write colour (RGB) frames: the gray scene as their luma, the part tinted warm and the
    /// background cool
    #[arg(long)]
    pub colour: bool,
    /// Write one of the evaluations' sequences instead (`coopwin experiment appearance` and
    /// `real-images`, e.g. centre-rotate, centre-combined, corner-lamp, or `long-term`, e.g.
    /// lookalike-front, crowd, panel), with its ground truth
    #[arg(long, value_name = "NAME", conflicts_with_all = ["path", "speed", "frames", "lighting", "clutter", "occlusion", "noise", "seed", "photo", "size"])]
    pub set: Option<String>,
    /// Output folder
    #[arg(long)]
    pub out: PathBuf,
    /// Write into a folder that is not empty (the scene's own files are replaced)
    #[arg(long)]
    pub force: bool,
}

/// Writes the scene the options describe and says so.
pub fn write_scene_files(args: SceneArgs) -> Result<(), CliError> {
    if let Some(name) = &args.set {
        if let Some(set) = longterm::sets().into_iter().find(|s| s.name == name.as_str()) {
            let n = write_long_term(&set, &args.out, args.force)?;
            println!("wrote {n} frames of {name} ({} frames/s), groundtruth.csv, truth.csv and fingerprint.txt to {}", longterm::FPS, args.out.display());
            return Ok(());
        }
        let sets: Vec<_> = appearance::conditions().into_iter().chain(real_images::conditions()).collect();
        let Some(c) = sets.iter().find(|c| &c.name == name) else {
            let names: Vec<&str> = sets.iter().map(|c| c.name.as_str()).chain(longterm::sets().iter().map(|s| s.name)).collect();
            return Err(CliError::arg(format!("--set {name}: no such sequence; the sequences are {}", names.join(", "))));
        };
        let n = write_scene(c.scene.clone(), &args.out, args.force, args.colour)?;
        println!("wrote {n} frames of {name} ({} frames/s) and groundtruth.csv to {}", c.scene.fps, args.out.display());
        return Ok(());
    }
    let cfg = SceneConfig {
        path: match args.path {
            PathArg::Pendulum => PathKind::Pendulum,
            PathArg::Triangle => PathKind::Triangle,
            PathArg::Swing => PathKind::Swing,
        },
        speed: args.speed,
        frames: args.frames,
        lighting_ramp: args.lighting == LightingArg::Ramp,
        clutter: args.clutter,
        occlusion: args.occlusion,
        noise: args.noise,
        seed: args.seed,
        photo: args.photo,
        width: args.size.0,
        height: args.size.1,
        ..SceneConfig::default()
    };
    let n = write_scene(cfg, &args.out, args.force, args.colour)?;
    println!("wrote {n} frames and groundtruth.csv to {}", args.out.display());
    Ok(())
}

/// Most frames `scene` writes: 20 000 frames is about three minutes at 114 frames/s.
pub const MAX_FRAMES: usize = 20_000;

/// Renders every frame of `cfg` into `out` as `frame_00000.png`... (8-bit gray, or RGB with
/// `colour`), and `groundtruth.csv`.
/// `out` must be a new or empty folder (its parent must exist), or, with `force`, a folder
/// whose files are kept apart from the scene's own; `force` never mixes two scenes: it refuses
/// a folder holding frames numbered past this scene's last.
pub fn write_scene(cfg: SceneConfig, out: &Path, force: bool, colour: bool) -> Result<usize, CliError> {
    let number = |name: &str, v: f64, max: f64| {
        if v.is_nan() {
            Err(CliError::arg(format!("--{name} {v}: not a number")))
        } else if !(0.0..=max).contains(&v) {
            let shown = if v.abs() < 1e6 { format!("{v}") } else { format!("{v:e}") };
            Err(CliError::arg(format!("--{name} must be 0..{max}, got {shown}")))
        } else {
            Ok(())
        }
    };
    number("speed", cfg.speed, 10_000.0)?;
    number("noise", cfg.noise, 255.0)?;
    prepare_folder(out, cfg.frames, force)?;
    let (w, h, n) = (cfg.width as u32, cfg.height as u32, cfg.frames);
    let scene = Scene::new(cfg);
    let mut truth = Vec::with_capacity(n);
    for k in 0..n {
        let path = out.join(format!("frame_{k:05}.png"));
        let mismatch = || CliError::new("internal: frame buffer size mismatch");
        let (saved, t) = if colour {
            let (pixels, t) = scene.render_colour(k);
            (image::RgbImage::from_raw(w, h, pixels).ok_or_else(mismatch)?.save(&path), t)
        } else {
            let (pixels, t) = scene.render(k);
            (image::GrayImage::from_raw(w, h, pixels).ok_or_else(mismatch)?.save(&path), t)
        };
        saved.map_err(|e| CliError::new(format!("cannot write {}: {e}", path.display())))?;
        truth.push(t);
    }
    OutFile::check(&out.join("groundtruth.csv"), "--out")?.write(groundtruth::to_csv(truth).as_bytes())?;
    Ok(n)
}

/// Checks that `out` may take a scene of `frames` frames (see [`write_scene`]) and creates it.
fn prepare_folder(out: &Path, frames: usize, force: bool) -> Result<(), CliError> {
    if frames == 0 || frames > MAX_FRAMES {
        return Err(CliError::arg(format!("--frames must be 1..{MAX_FRAMES}, got {frames}")));
    }
    if check_folder(out, "--out")? {
        let entries: Vec<String> = std::fs::read_dir(out)
            .map_err(|e| io_error("read", out, e))?
            .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
            .collect();
        if !entries.is_empty() && !force {
            return Err(CliError::arg(format!(
                "--out {}: the folder is not empty ({} entries); give a new folder, or --force to write the scene's files into it",
                out.display(),
                entries.len()
            )));
        }
        let stale = entries.iter().filter(|e| frame_number(e).is_some_and(|k| k >= frames)).count();
        if stale > 0 {
            return Err(CliError::arg(format!(
                "--out {}: the folder holds {stale} frame(s) numbered past this scene's {frames} frames; they would mix two scenes: give a new folder",
                out.display()
            )));
        }
    }
    create_folder(out, "--out")
}

/// Writes a long-term set's frames into `out` as [`write_scene`] does, its `groundtruth.csv`
/// (the target's centre, `visible` 0 where it is hidden or gone) and `truth.csv`
/// (`frame,x,y,w,h,state`: the target's box as OpenCV's `x,y,w,h` and `visible`, `hidden` or
/// `gone`, the columns of the hand-labelled clips in `fixtures/longterm/`), and
/// `fingerprint.txt` (the frames' fingerprint, which `scripts/opencv_longterm.py --sets` keeps
/// beside OpenCV's results on them).
pub fn write_long_term(set: &longterm::LongTermSet, out: &Path, force: bool) -> Result<usize, CliError> {
    prepare_folder(out, longterm::FRAMES, force)?;
    let frames = set.render_all();
    let (w, h) = (longterm::WIDTH as u32, longterm::HEIGHT as u32);
    let half = (longterm::SIDE - 1.0) / 2.0;
    let mut boxes = String::from("frame,x,y,w,h,state\n");
    let mut truth = Vec::new();
    for (k, t) in frames.truth.iter().enumerate() {
        let path = out.join(format!("frame_{k:05}.png"));
        let pixels = frames.pixels(k).map(<[u8]>::to_vec).unwrap_or_default();
        let img = image::GrayImage::from_raw(w, h, pixels).ok_or_else(|| CliError::new("internal: frame buffer size mismatch"))?;
        img.save(&path).map_err(|e| CliError::new(format!("cannot write {}: {e}", path.display())))?;
        let (x, y) = t.centre;
        let _ = writeln!(boxes, "{k},{:.3},{:.3},{},{},{}", x - half, y - half, longterm::SIDE, longterm::SIDE, t.presence.name());
        truth.push(Truth { frame: k, centre: t.centre, corner: t.centre, visible: t.presence == Presence::Visible });
    }
    OutFile::check(&out.join("groundtruth.csv"), "--out")?.write(groundtruth::to_csv(truth).as_bytes())?;
    OutFile::check(&out.join("truth.csv"), "--out")?.write(boxes.as_bytes())?;
    OutFile::check(&out.join("fingerprint.txt"), "--out")?.write((frames.fingerprint() + "\n").as_bytes())?;
    Ok(frames.truth.len())
}

/// K for a file named `frame_K.png` (as [`write_scene`] names frames).
fn frame_number(name: &str) -> Option<usize> {
    name.strip_prefix("frame_")?.strip_suffix(".png")?.parse().ok()
}
