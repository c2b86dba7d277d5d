//! The README's quick tour, run as written: the `vouch` lines of its first `sh` block, read from
//! README.md so that the tour cannot drift from what the binary does. Each runs from the
//! repository root with the built binary on the `PATH` and `$out` a scratch directory; the exit
//! code must be the one the line's comment gives (`(exit N)`, else 0), no line may print a
//! warning, and nothing may be written into the repository.

mod common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::code;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// One command of the tour: the shell line, its explanation and the exit code it documents.
struct Step {
    line: String,
    says: String,
    exit: i32,
}

/// The commands of the first `sh` block after the `## Quick tour` heading.
fn tour(readme: &str) -> (Vec<Step>, String) {
    let from = readme.find("## Quick tour").expect("README has a quick tour");
    let block = readme[from..].split("```sh\n").nth(1).expect("an sh block");
    let block = block.split("```").next().expect("a closed block").to_string();
    let steps = block
        .lines()
        .filter(|l| l.starts_with("vouch "))
        .map(|l| {
            let (cmd, says) = l.split_once("  # ").unwrap_or((l, ""));
            let exit = says
                .split("(exit ")
                .nth(1)
                .and_then(|r| r.split(')').next())
                .map_or(0, |n| n.parse().expect("an exit code"));
            Step { line: cmd.trim().to_string(), says: says.trim().to_string(), exit }
        })
        .collect();
    (steps, block)
}

/// What the repository root holds (names), so that a step writing into it is noticed.
fn root_entries() -> BTreeSet<String> {
    std::fs::read_dir(root())
        .expect("repository root")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect()
}

/// Signs of a warning in any of the message formats, and upstream's unexplained SRTM line.
const WARNING_SIGNS: &[&str] = &["⚠", "warning", "::W0", "No SRTM"];

#[test]
fn the_quick_tour_runs_as_written() {
    let readme = std::fs::read_to_string(root().join("README.md")).expect("README.md");
    let (steps, block) = tour(&readme);
    assert!(block.contains("out=$(mktemp -d)"), "the tour names its scratch directory");
    assert!(steps.len() >= 15, "{} commands in the tour", steps.len());
    let bin = Path::new(env!("CARGO_BIN_EXE_vouch")).parent().expect("bin dir").to_path_buf();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let scratch = tempfile::tempdir().expect("scratch directory");
    let before = root_entries();
    let mut failed = vec![];
    for step in &steps {
        assert!(!step.says.is_empty(), "`{}` does not say what it prints", step.line);
        let o = Command::new("bash")
            .args(["-c", &step.line])
            .current_dir(root())
            .env("PATH", &path)
            .env("out", scratch.path())
            .output()
            .expect("bash runs");
        let stderr = String::from_utf8_lossy(&o.stderr);
        if code(&o) != step.exit {
            failed.push(format!(
                "`{}`: exit {}, README says {}\n{stderr}",
                step.line,
                code(&o),
                step.exit
            ));
        }
        // A line the README itself quotes in the step's comment is explained, not a surprise.
        let unexplained = |s: &&&str| stderr.contains(**s) && !step.says.contains(**s);
        if let Some(sign) = WARNING_SIGNS.iter().find(unexplained) {
            failed.push(format!("`{}` warns (`{sign}`):\n{stderr}", step.line));
        }
    }
    assert_eq!(root_entries(), before, "the tour wrote into the repository root");
    for f in ["flight_plan.h", "flight_plan.xml", "demo.svg", "plan.png", "report.json"] {
        assert!(scratch.path().join(f).is_file(), "the tour writes $out/{f}");
    }
    assert!(failed.is_empty(), "{}", failed.join("\n\n"));
}

/// The set-up command: the README's first `sh` block builds and then runs each family's main job
/// on a bundled example. The `vouch` parts of its `&&` chain are run here as written; each must
/// succeed (exit 0) on the examples alone.
#[test]
fn the_set_up_command_runs_a_bundled_example_of_each_family() {
    let readme = std::fs::read_to_string(root().join("README.md")).expect("README.md");
    let from = readme.find("## Set up").expect("README has a set-up section");
    let block = readme[from..].split("```sh\n").nth(1).expect("an sh block");
    let line = block.split("```").next().expect("a closed block").trim();
    assert!(line.starts_with("cargo build --release"), "the set-up command builds first: {line}");
    let jobs: Vec<&str> =
        line.split(" && ").map(str::trim).filter(|part| part.starts_with("vouch ")).collect();
    for family in ["vouch fpl ", "vouch mav ", "vouch navfn "] {
        assert!(
            jobs.iter().any(|j| j.starts_with(family)),
            "the set-up command runs a `{family}` job: {line}"
        );
    }
    let bin = Path::new(env!("CARGO_BIN_EXE_vouch")).parent().expect("bin dir").to_path_buf();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let before = root_entries();
    for job in jobs {
        let o = Command::new("bash")
            .args(["-c", job])
            .current_dir(root())
            .env("PATH", &path)
            .output()
            .expect("bash runs");
        assert_eq!(code(&o), 0, "`{job}`: {}", String::from_utf8_lossy(&o.stderr));
        assert!(!o.stdout.is_empty(), "`{job}` prints what it found");
    }
    assert_eq!(root_entries(), before, "the set-up command wrote into the repository root");
}
