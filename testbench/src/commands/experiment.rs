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
    let mut sections = Vec::new();
    for e in chosen {
        eprintln!("experiment {}", e.name());
        let md = e.reproduce(&mut ctx)?;
        println!("{md}");
        sections.push(md);
    }
    let earlier = std::fs::read_to_string(&results.path).unwrap_or_default();
    results.write(merged(&earlier, &sections).as_bytes())?;
    println!("wrote {}", results.path.display());
    Ok(())
}

/// `results.md`: the `earlier` file's sections (each from its `## name` line) with those of
/// the experiments just run in their place, new ones after; rerunning one experiment into a
/// folder keeps the others' sections.
fn merged(earlier: &str, sections: &[String]) -> String {
    let name = |section: &str| section.strip_prefix("## ").and_then(|h| h.split_whitespace().next()).map(str::to_owned);
    let mut kept: Vec<String> = Vec::new();
    for line in earlier.lines().skip_while(|l| !l.starts_with("## ")) {
        match kept.last_mut() {
            Some(last) if !line.starts_with("## ") => {
                last.push_str(line);
                last.push('\n');
            }
            _ => kept.push(format!("{line}\n")),
        }
    }
    for new in sections {
        match kept.iter_mut().find(|old| name(old) == name(new)) {
            Some(old) => old.clone_from(new),
            None => kept.push(new.clone()),
        }
    }
    // A blank line between sections, as markdown needs before a heading.
    let spaced = kept.into_iter().map(|s| if s.ends_with("\n\n") { s } else { s + "\n" });
    std::iter::once("# Experiments\n\n".to_owned()).chain(spaced).collect()
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

#[cfg(test)]
mod tests {
    use super::merged;

    #[test]
    fn a_rerun_replaces_its_own_section_and_keeps_the_others() {
        // By hand: two sections, the second rerun, a third new.
        let earlier = "# Experiments\n\n## fig-2.9 (c40 profile)\n\nold 2.9\n\n## long-term\n\nold lt\n\n";
        let new = ["## long-term\n\nnew lt\n\n".to_owned(), "## table-4.1 (c40 profile)\n\nt\n\n".to_owned()];
        let want = "# Experiments\n\n## fig-2.9 (c40 profile)\n\nold 2.9\n\n## long-term\n\nnew lt\n\n## table-4.1 (c40 profile)\n\nt\n\n";
        assert_eq!(merged(earlier, &new), want);
        assert_eq!(merged("", &new[..1]), "# Experiments\n\n## long-term\n\nnew lt\n\n");
    }
}
