//! `coopwin experiment`: reproduces a table or figure of the thesis, or all of them, into a
//! folder, with `results.md` collecting their sections.
use super::args::{HdlArg, ProfileArg};
use super::output::{create_folder, OutFile};
use super::CliError;
use crate::experiments::{appearance, real_images};
use crate::experiments::{Context, Experiment};
use std::path::{Path, PathBuf};

/// `coopwin experiment`'s options.
#[derive(clap::Args)]
pub struct ExperimentArgs {
    /// table-2.3, fig-2.9, fig-2.10, fig-3.5, fig-3.7, fig-3.10, table-4.1, real-images,
    /// appearance, real-footage, long-term, or all
    pub name: String,
    /// Output folder
    #[arg(long)]
    pub out: PathBuf,
    /// Processor speeds
    #[arg(long, value_enum, default_value_t = ProfileArg::C40)]
    pub profile: ProfileArg,
    /// Window units: the behavioural model, the rust-hdl blocks, or the Verilog in Verilator
    #[arg(long, value_enum, default_value_t = HdlArg::Model)]
    pub hdl: HdlArg,
    /// Where the real clips are (real-footage: Megamind.avi, Megamind_bugy.avi, tree.avi)
    #[arg(long, value_name = "DIR", default_value = crate::experiments::real_footage::DEFAULT_CLIPS)]
    pub clips: PathBuf,
    /// Also write the real-image and appearance sequences (PNG frames + groundtruth.csv)
    /// under DIR, the input of scripts/opencv_real.py
    #[arg(long, value_name = "DIR")]
    pub sequences: Option<PathBuf>,
}

/// Runs the experiments named, printing each section, and writes `results.md`.
pub fn write_results(args: ExperimentArgs) -> Result<(), CliError> {
    if let Some(root) = &args.sequences {
        create_folder(root, "--sequences")?;
        write_sequences(root)?;
    }
    let Some(chosen) = Experiment::select(&args.name) else {
        return Err(CliError::arg(format!("unknown experiment '{}'; expected one of {} or all", args.name, Experiment::names().join(", "))));
    };
    create_folder(&args.out, "--out")?;
    let results = OutFile::check(&args.out.join("results.md"), "--out")?;
    let mut progress = |s: &str| eprintln!("  {s}");
    let mut ctx = Context::new(&args.out, args.profile.into(), args.hdl.into(), &mut progress);
    ctx.clips = args.clips.clone();
    let mut all = String::from("# Experiments\n\n");
    for e in chosen {
        eprintln!("experiment {}", e.name());
        let md = e.reproduce(&mut ctx)?;
        println!("{md}");
        all.push_str(&md);
    }
    results.write(all.as_bytes())?;
    println!("wrote {}", results.path.display());
    Ok(())
}

/// Writes every real-image and appearance condition's frames, `groundtruth.csv` and `fingerprint.txt` (the
/// frames' fingerprint) under `root/<name>/`, the input of `scripts/opencv_real.py`.
fn write_sequences(root: &Path) -> Result<(), CliError> {
    for c in real_images::conditions().into_iter().chain(appearance::conditions()) {
        eprintln!("  sequence {}", c.name);
        let dir = root.join(&c.name);
        // A refused folder here is a failure of the run (exit 1), not of an argument.
        super::scene::write_scene(c.scene.clone(), &dir, false, false).map_err(|e| CliError::new(e.message))?;
        let fp = dir.join("fingerprint.txt");
        std::fs::write(&fp, c.render().fingerprint() + "\n").map_err(|e| CliError::new(format!("cannot write {}: {e}", fp.display())))?;
    }
    Ok(())
}
