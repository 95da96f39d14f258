//! The thesis's experiments, reproduced on synthetic scenes with ground truth: one file per
//! table or figure, chosen by [`Experiment`]. Each thesis experiment writes a CSV, a chart (SVG
//! and PNG) and a markdown section that puts the thesis's numbers next to ours; the real-image
//! evaluation compares coopwin with OpenCV's trackers.
//!
//! A new experiment is a file here, an [`Experiment`] variant and its arm in
//! [`Experiment::reproduce`].
pub mod appearance;
pub mod fig_2_10;
pub mod fig_2_9;
pub mod fig_3_10;
pub mod fig_3_5;
pub mod fig_3_7;
pub mod long_term;
pub mod real_footage;
pub mod real_images;
pub mod setup;
pub mod speed_sweep;
pub mod table_2_3;
pub mod table_4_1;
pub mod threshold_sweep;

use crate::report::plot::{self, Chart, PlotError, Series};
use crate::system::cost::CostModel;
use crate::system::{SimError, SystemConfig};
use crate::units::UnitBackend;
use clap::ValueEnum;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A table or figure of the thesis, by its name on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Experiment {
    /// Table 2.3: lock-on, tracking and recovery times of SPMF, TPDF and MPDF.
    #[value(name = "table-2.3")]
    Table2_3,
    /// Fig. 2.9: RMS error against target speed.
    #[value(name = "fig-2.9")]
    Fig2_9,
    /// Fig. 2.10: lock-on time against target speed.
    #[value(name = "fig-2.10")]
    Fig2_10,
    /// Figs. 3.5/3.6: the corner detector's location error against its threshold.
    #[value(name = "fig-3.5")]
    Fig3_5,
    /// Fig. 3.7: loss of tracking, multi-window against a single window.
    #[value(name = "fig-3.7")]
    Fig3_7,
    /// Figs. 3.8/3.10: edge information and the corner detector's I_cd.
    #[value(name = "fig-3.10")]
    Fig3_10,
    /// Table 4.1: NCC, CD and COOP under the lamp change.
    #[value(name = "table-4.1")]
    Table4_1,
    /// The real-image evaluation against OpenCV's trackers (native profile).
    #[value(name = "real-images")]
    RealImages,
    /// Appearance changes (rotation, scale, tilt, shadow, blur, cover) against OpenCV's
    /// trackers (native profile).
    #[value(name = "appearance")]
    Appearance,
    /// Objects in real clips (Debian's opencv-doc), against OpenCV's trackers, without ground
    /// truth: positions, forward-backward error, agreement with CSRT.
    #[value(name = "real-footage")]
    RealFootage,
    /// Long-term sets: look-alikes, occluders and a target that leaves, scored by the
    /// precision of the `ok` 1 rows, their recall and the silence while the target is hidden
    /// or gone (VOT-LT, OxUvA).
    #[value(name = "long-term")]
    LongTerm,
}

impl Experiment {
    /// The name on the command line.
    pub fn name(self) -> String {
        self.to_possible_value().map(|v| v.get_name().to_string()).unwrap_or_default()
    }

    /// `all` (every experiment, in order) or one experiment's name; `None` for another name.
    pub fn select(name: &str) -> Option<Vec<Experiment>> {
        match name {
            "all" => Some(Experiment::value_variants().to_vec()),
            n => Experiment::from_str(n, false).ok().map(|e| vec![e]),
        }
    }

    /// Every experiment's name, in order.
    pub fn names() -> Vec<String> {
        Experiment::value_variants().iter().map(|e| e.name()).collect()
    }

    /// Runs the experiment with `ctx`'s settings, writing into its folder; returns its
    /// markdown section.
    pub fn reproduce(self, ctx: &mut Context) -> Result<String, ExperimentError> {
        let body = match self {
            Experiment::Table2_3 => table_2_3::reproduce,
            Experiment::Fig2_9 => fig_2_9::reproduce,
            Experiment::Fig2_10 => fig_2_10::reproduce,
            Experiment::Fig3_5 => fig_3_5::reproduce,
            Experiment::Fig3_7 => fig_3_7::reproduce,
            Experiment::Fig3_10 => fig_3_10::reproduce,
            Experiment::Table4_1 => table_4_1::reproduce,
            Experiment::RealImages => return real_images::evaluate(ctx.dir, ctx.progress),
            Experiment::Appearance => return appearance::evaluate(ctx.dir, ctx.progress),
            Experiment::RealFootage => return real_footage::evaluate(ctx.dir, &ctx.clips, ctx.progress),
            Experiment::LongTerm => return long_term::evaluate(ctx.dir, &ctx.clips, ctx.progress),
        };
        ctx.thesis_section(self.name(), body)
    }
}

/// What an experiment runs with: where it writes, the processors' speeds, the window units,
/// and where its progress goes.
pub struct Context<'a> {
    /// The output folder.
    pub dir: &'a Path,
    /// Processor speeds.
    pub profile: CostModel,
    /// Window units.
    pub backend: UnitBackend,
    /// Progress lines (one per run).
    pub progress: &'a mut dyn FnMut(&str),
    /// Where the real clips are (`real-footage`).
    pub clips: PathBuf,
    /// The experiment running, naming its files.
    name: String,
}

impl<'a> Context<'a> {
    /// A context writing into `dir`.
    pub fn new(dir: &'a Path, profile: CostModel, backend: UnitBackend, progress: &'a mut dyn FnMut(&str)) -> Self {
        Context { dir, profile, backend, progress, clips: real_footage::DEFAULT_CLIPS.into(), name: String::new() }
    }

    /// `cfg` on this context's window units.
    pub fn config(&self, cfg: SystemConfig) -> SystemConfig {
        SystemConfig { backend: self.backend, ..cfg }
    }

    /// Reports progress.
    pub fn say(&mut self, what: &str) {
        (self.progress)(what);
    }

    /// Target speeds swept, in px/s: the thesis's range; with our kernels' speed every update
    /// fits a frame, so the native profile goes further to find where each strategy loses the
    /// target.
    pub fn speeds(&self) -> Vec<f64> {
        let step = if self.profile.name == "native" { 40.0 } else { 20.0 };
        (1..=8).map(|k| step * f64::from(k)).collect()
    }

    /// Writes the experiment's CSV, `NAME.csv`.
    pub fn write_csv(&self, text: &str) -> Result<(), ExperimentError> {
        write_file(&self.dir.join(format!("{}.csv", self.name)), text)
    }

    /// Writes the experiment's chart, `NAME.svg` and `NAME.png`.
    pub fn write_chart(&self, chart: &Chart) -> Result<(), ExperimentError> {
        plot::write(chart, self.dir, &self.name).map_err(ExperimentError::Plot)
    }

    /// A thesis experiment's section: a heading with the profile and the units, `body`'s
    /// text, the files written; also written to `NAME.md`.
    fn thesis_section(&mut self, name: String, body: fn(&mut Context) -> Result<String, ExperimentError>) -> Result<String, ExperimentError> {
        std::fs::create_dir_all(self.dir).map_err(|source| ExperimentError::Io { action: "create", path: self.dir.into(), source })?;
        let units = if self.backend == UnitBackend::RustHdl { ", rust-hdl window units" } else { "" };
        let mut md = format!("## {name} ({} profile{units})\n\n", self.profile.name);
        self.name = name;
        md.push_str(&body(self)?);
        let name = &self.name;
        let _ = writeln!(md, "\nFiles: `{name}.csv`, `{name}.svg`, `{name}.png`.\n");
        write_file(&self.dir.join(format!("{name}.md")), &md)?;
        Ok(md)
    }
}

/// Writes a result file.
fn write_file(path: &Path, text: &str) -> Result<(), ExperimentError> {
    std::fs::write(path, text).map_err(|source| ExperimentError::Io { action: "write", path: path.into(), source })
}

/// A chart's series from its points.
pub fn series(label: &str, pts: impl Iterator<Item = (f64, Option<f64>)>) -> Series {
    Series { label: label.to_string(), points: pts.collect() }
}

/// Why an experiment failed.
#[derive(Debug)]
pub enum ExperimentError {
    /// A run failed.
    Run(SimError),
    /// A chart could not be written.
    Plot(PlotError),
    /// A file or folder could not be made.
    Io {
        /// `create` or `write`.
        action: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// A real clip could not be decoded.
    Clip {
        /// The clip.
        path: PathBuf,
        /// Why.
        why: String,
    },
    /// An OpenCV fixture has a bad line.
    Fixture {
        /// The fixture.
        path: PathBuf,
        /// Line number, from 1.
        line: usize,
    },
}

impl std::fmt::Display for ExperimentError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExperimentError::Run(e) => write!(f, "{e}"),
            ExperimentError::Plot(e) => write!(f, "{e}"),
            ExperimentError::Io { action, path, source } => write!(f, "cannot {action} {}: {source}", path.display()),
            ExperimentError::Clip { path, why } => write!(f, "{}: {why}", path.display()),
            ExperimentError::Fixture { path, line } => write!(f, "{}: line {line}: not a line of this fixture's columns", path.display()),
        }
    }
}

impl std::error::Error for ExperimentError {}

wrap_errors!(ExperimentError { Run(SimError), Plot(PlotError) });
