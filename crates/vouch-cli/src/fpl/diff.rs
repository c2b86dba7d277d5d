//! `vouch fpl diff`: two versions of a plan compared by behaviour (and structure), from two
//! files or from git (`--git REV`: the old version as committed at REV, its included
//! procedures too).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use clap::Args;
use vouch_fpl::ast::FlightPlan;
use vouch_fpl::diff::{self, DiffOptions, DiffReport, Verdict, Version};
use vouch_fpl::span::SourceFile;

use super::{lowered, rejected};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch fpl diff`.
#[derive(Args)]
pub struct DiffArgs {
    /// OLD.xml NEW.xml; with --git, the plans to compare with their version at REV (default:
    /// every flight plan that changed since REV)
    #[arg(value_name = "PLAN")]
    plans: Vec<PathBuf>,
    /// Read the old version of each plan (and of its included procedures) from this git
    /// revision
    #[arg(long, value_name = "REV")]
    git: Option<String>,
    /// Leave out the ground station's block jumps between calls (compare the plans' own runs
    /// only)
    #[arg(long)]
    no_operator_jumps: bool,
    /// State-pair budget (the verdict is "undecided" when it cuts the walk)
    #[arg(long, default_value_t = 1_000_000)]
    max_states: usize,
    /// Directory searched for included procedures after the plan's own directory (repeatable)
    #[arg(long = "include-dir", value_name = "DIR")]
    include_dirs: Vec<PathBuf>,
    /// One JSON document (`format`, then one report per pair) on standard output
    #[arg(long)]
    json: bool,
}

/// One pair to compare: the files to read and the names to print.
struct Pair {
    old: PathBuf,
    new: PathBuf,
    /// The old version's name when it comes from git (`REV:path`) and the checkout it was
    /// written to (kept alive until the pair is compared).
    from_git: Option<(String, tempfile::TempDir, PathBuf)>,
}

/// `vouch fpl diff`.
pub fn diff(a: DiffArgs, ctx: &mut Ctx) -> CmdResult {
    let pairs = match &a.git {
        None => {
            let [old, new] = a.plans.as_slice() else {
                return Err(Failure::usage(
                    "vouch fpl diff needs OLD.xml NEW.xml, or --git REV [PLAN...]",
                ));
            };
            vec![Pair { old: old.clone(), new: new.clone(), from_git: None }]
        }
        Some(rev) => git_pairs(rev, &a.plans)?,
    };
    if pairs.is_empty() {
        // Nothing compared: said, so that a silent exit 0 is not read as "checked, equivalent".
        ctx.note("no flight plan changed: nothing to compare");
    }
    let opts = DiffOptions {
        operator_jumps: !a.no_operator_jumps,
        max_states: a.max_states,
        ..DiffOptions::default()
    };
    let mut reports = Vec::new();
    for p in &pairs {
        reports.push(compare(&a, ctx, p, &opts)?);
    }
    if a.json {
        ctx.out.json(&diff::Document { format: diff::FORMAT, diffs: &reports })?;
    } else {
        for (p, r) in pairs.iter().zip(&reports) {
            ctx.out.text(&diff::render(r))?;
            if let Some(d) = &r.divergence {
                let args = diff::replay_args(d);
                let old = match &p.from_git {
                    Some((name, ..)) => format!("{name} (checked out)"),
                    None => p.old.display().to_string(),
                };
                ctx.out.text(&format!(
                    "replay:\n  vouch fpl sim {old}{args}\n  vouch fpl sim {}{args}\n",
                    p.new.display()
                ))?;
            }
        }
    }
    let all_equivalent = reports.iter().all(|r| r.verdict == Verdict::Equivalent);
    Ok(if all_equivalent { Exit::Ok } else { Exit::Findings })
}

fn load(a: &DiffArgs, ctx: &Ctx, path: &Path, extra: Option<&Path>) -> Result<FlightPlan, Failure> {
    let mut search_dirs = a.include_dirs.clone();
    search_dirs.extend(extra.map(Path::to_path_buf));
    let opts = vouch_fpl::front::Options { search_dirs, ..Default::default() };
    let plan = vouch_fpl::front::parse_file_with(path, &opts).map_err(rejected)?;
    for w in &plan.warnings {
        ctx.warn(w);
    }
    Ok(plan)
}

fn compare(a: &DiffArgs, ctx: &Ctx, p: &Pair, opts: &DiffOptions) -> Result<DiffReport, Failure> {
    let new = load(a, ctx, &p.new, None)?;
    let mut old = match &p.from_git {
        Some((_, dir, search)) => load(a, ctx, &p.old, Some(&dir.path().join(search)))?,
        None => load(a, ctx, &p.old, None)?,
    };
    if let Some((name, dir, _)) = &p.from_git {
        rename_sources(&mut old, dir.path(), name);
    }
    let (fa, fb) = (lowered(&old)?, lowered(&new)?);
    diff::diff(Version { plan: &old, fp: &fa }, Version { plan: &new, fp: &fb }, opts)
        .map_err(Failure::rejected)
}

/// Shows files of a git checkout as `REV:path`.
fn rename_sources(plan: &mut FlightPlan, root: &Path, name: &str) {
    let rev = name.split(':').next().unwrap_or(name);
    let prefix = format!("{}/", root.display());
    for f in &mut plan.sources.files {
        if let Some(rel) = f.path.strip_prefix(&prefix) {
            *f = Arc::new(SourceFile { path: format!("{rev}:{rel}"), text: f.text.clone() });
        }
    }
}

fn git(dir: &Path, args: &[&str]) -> Result<Vec<u8>, Failure> {
    let out = Command::new("git")
        .arg("-C")
        .arg(dir)
        .args(args)
        .output()
        .map_err(|e| Failure::usage(format_args!("cannot run git: {e}")))?;
    if !out.status.success() {
        return Err(Failure::usage(format_args!(
            "git {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    Ok(out.stdout)
}

fn lines(bytes: Vec<u8>) -> Vec<String> {
    String::from_utf8_lossy(&bytes).lines().map(str::to_string).filter(|l| !l.is_empty()).collect()
}

/// The plans to compare with `REV`: the ones named, or every `.xml` that changed since REV
/// and is a flight plan now.
fn git_pairs(rev: &str, plans: &[PathBuf]) -> Result<Vec<Pair>, Failure> {
    let cwd = std::env::current_dir().map_err(Failure::usage)?;
    let root = PathBuf::from(lines(git(&cwd, &["rev-parse", "--show-toplevel"])?).join(""));
    let plans: Vec<PathBuf> = if plans.is_empty() {
        lines(git(&root, &["diff", "--name-only", rev, "--", "*.xml"])?)
            .into_iter()
            .map(|rel| root.join(rel))
            .filter(|p| std::fs::read_to_string(p).is_ok_and(|t| t.contains("<flight_plan")))
            .collect()
    } else {
        plans.to_vec()
    };
    plans.iter().map(|p| git_pair(rev, &root, p)).collect()
}

/// Writes the old version of `plan`, its directory and the procedure directory (the nearest
/// ancestor holding `flight_plan.dtd`) as committed at `rev` into a temporary checkout.
fn git_pair(rev: &str, root: &Path, plan: &Path) -> Result<Pair, Failure> {
    let abs = std::fs::canonicalize(plan).map_err(|e| Failure::io(plan, &e))?;
    let root = std::fs::canonicalize(root).map_err(|e| Failure::io(root, &e))?;
    let rel = abs.strip_prefix(&root).map_err(|_| {
        Failure::usage(format_args!("{} is not inside the git repository", plan.display()))
    })?;
    let procedures = abs
        .ancestors()
        .skip(1)
        .find(|d| d.join("flight_plan.dtd").is_file())
        .and_then(|d| d.strip_prefix(&root).ok())
        .map(Path::to_path_buf);
    let dir = tempfile::tempdir().map_err(Failure::usage)?;
    let mut folders: Vec<PathBuf> = rel.parent().map(Path::to_path_buf).into_iter().collect();
    folders.extend(procedures.clone());
    for folder in folders {
        let spec = if folder.as_os_str().is_empty() {
            ".".to_string()
        } else {
            folder.display().to_string()
        };
        let listed = lines(git(&root, &["ls-tree", "-r", "--name-only", rev, "--", &spec])?);
        for file in listed.iter().filter(|f| f.ends_with(".xml") || f.ends_with(".dtd")) {
            let bytes = git(&root, &["show", &format!("{rev}:{file}")])?;
            let target = dir.path().join(file);
            if let Some(parent) = target.parent() {
                std::fs::create_dir_all(parent).map_err(|e| Failure::io(parent, &e))?;
            }
            std::fs::write(&target, bytes).map_err(|e| Failure::io(&target, &e))?;
        }
    }
    let old = dir.path().join(rel);
    if !old.is_file() {
        return Err(Failure::usage(format_args!("{} does not exist at {rev}", rel.display())));
    }
    let name = format!("{rev}:{}", rel.display());
    Ok(Pair {
        old,
        new: plan.to_path_buf(),
        from_git: Some((name, dir, procedures.unwrap_or_default())),
    })
}
