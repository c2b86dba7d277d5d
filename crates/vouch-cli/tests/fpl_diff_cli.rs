//! `vouch fpl diff` from the command line (two files, `--json`, `--git`), the replay it prints
//! (`vouch fpl sim --answers --jump`), and the bundled example: no warning from `compile` or
//! `lint`, and `lint` reporting what `compile` warns about.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{code, vouch};

fn demo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fpl/demo.xml")
}

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The demo with Survey's tower circle made larger (radius 80 → 120).
fn changed_demo(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(demo()).expect("demo");
    let changed = text.replacen("radius=\"80\"", "radius=\"120\"", 1);
    assert_ne!(changed, text);
    let p = dir.join("demo_changed.xml");
    std::fs::write(&p, changed).expect("write");
    p
}

#[test]
fn the_bundled_example_compiles_and_lints_without_a_warning() {
    let d = demo().display().to_string();
    let dir = tempfile::tempdir().expect("tempdir");
    let h = dir.path().join("flight_plan.h").display().to_string();
    let o = vouch(&["fpl", "compile", &d, "-o", &h]);
    assert_eq!(code(&o), 0);
    assert_eq!(String::from_utf8_lossy(&o.stderr), "", "compile warns");
    let o = vouch(&["fpl", "lint", &d]);
    assert_eq!(code(&o), 0);
    assert!(stdout(&o).ends_with("0 warning(s)\n"), "{}", stdout(&o));
    assert_eq!(String::from_utf8_lossy(&o.stderr), "");
}

#[test]
fn lint_reports_what_compile_warns_about() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = std::fs::read_to_string(demo()).expect("demo");
    // TD below ground_alt + security_height (150 + 30): upstream's low-altitude NOTICE.
    let low = text.replacen("y=\"10.0\" alt=\"180\"", "y=\"10.0\" alt=\"150\"", 1);
    assert_ne!(low, text);
    let p = dir.path().join("low.xml");
    std::fs::write(&p, low).expect("write");
    let p = p.display().to_string();
    let compile = vouch(&["--message-format", "short", "fpl", "compile", &p, "-o", "/dev/null"]);
    let lint = vouch(&["--message-format", "short", "fpl", "lint", &p, "--strict"]);
    let warned = |o: &std::process::Output| String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(warned(&compile).contains("warning[fpl::W022]"), "{}", warned(&compile));
    assert_eq!(warned(&lint), warned(&compile), "lint shows the same warnings");
    assert!(
        stdout(&lint).ends_with("1 warning(s) — fpl::W022: 1 (generator)\n"),
        "{}",
        stdout(&lint)
    );
    assert_eq!(code(&lint), 3, "--strict counts them");
}

#[test]
fn diff_of_two_files_text_and_json() {
    let dir = tempfile::tempdir().expect("tempdir");
    let new = changed_demo(dir.path());
    let (a, b) = (demo().display().to_string(), new.display().to_string());
    let same = vouch(&["fpl", "diff", &a, &a]);
    assert_eq!(code(&same), 0);
    assert!(stdout(&same).contains("behaviour: EQUIVALENT"));
    let o = vouch(&["fpl", "diff", &a, &b]);
    assert_eq!(code(&o), 3, "{}", stdout(&o));
    let text = stdout(&o);
    assert!(text.contains("behaviour: DIFFERENT"), "{text}");
    // Survey (block 3): the structural summary names the changed attribute.
    assert!(text.contains("~ circle: radius: \"80\" → \"120\""), "{text}");
    // The printed command replays the run on the new plan (a shell line, as a user runs it):
    // its last call circles at 120.
    let replay = text.lines().skip_while(|l| *l != "replay:").nth(2).expect("replay line");
    assert!(replay.trim().starts_with(&format!("vouch fpl sim {b} --answers '")), "{replay}");
    let line = replay.trim().replacen("vouch", env!("CARGO_BIN_EXE_vouch"), 1);
    let sim = Command::new("sh").arg("-c").arg(&line).output().expect("sh runs");
    assert_eq!(code(&sim), 0, "{line}: {}", String::from_utf8_lossy(&sim.stderr));
    assert!(stdout(&sim).contains("NavCircleWaypoint(6, 120)"), "{}", stdout(&sim));

    let j = vouch(&["fpl", "diff", "--json", &a, &b]);
    assert_eq!(code(&j), 3);
    let v: serde_json::Value = serde_json::from_slice(&j.stdout).expect("json");
    assert_eq!(v["format"], 1);
    let d = &v["diffs"][0];
    assert_eq!(d["verdict"], "different");
    assert_eq!(d["divergence"]["kind"], "event");
    let old = d["divergence"]["old"]["text"].as_str().expect("old text");
    assert_eq!(old, "X NavCircleWaypoint(6, 80)");
}

fn git(dir: &Path, args: &[&str]) {
    let o = Command::new("git")
        .args(["-c", "user.name=t", "-c", "user.email=t@t", "-C"])
        .arg(dir)
        .args(args)
        .output()
        .expect("git runs");
    assert!(o.status.success(), "git {args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn diff_against_a_git_revision_reads_the_old_plan_and_its_procedures() {
    let dir = tempfile::tempdir().expect("tempdir");
    let repo = dir.path();
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../vouch-fpl/tests/diff_plans");
    for f in ["with_procedure.xml", "landing_proc.xml"] {
        std::fs::copy(fixtures.join(f), repo.join(f)).expect("copy");
    }
    git(repo, &["init", "-q"]);
    git(repo, &["add", "."]);
    git(repo, &["commit", "-qm", "one"]);
    // Change the procedure only: the plan file itself is untouched.
    let p = repo.join("landing_proc.xml");
    let text = std::fs::read_to_string(&p).expect("read");
    std::fs::write(&p, text.replacen("@GT 0.50", "@GT 0.75", 1)).expect("write");
    let o = Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(["fpl", "diff", "--git", "HEAD", "with_procedure.xml"])
        .current_dir(repo)
        .output()
        .expect("runs");
    assert_eq!(code(&o), 3, "{}{}", stdout(&o), String::from_utf8_lossy(&o.stderr));
    let text = stdout(&o);
    assert!(text.starts_with("HEAD:with_procedure.xml → with_procedure.xml"), "{text}");
    assert!(
        text.contains("old: C 0 (NavCircleCount()>0.500000) at HEAD:landing_proc.xml:"),
        "{text}"
    );
    assert!(text.contains("new: C 0 (NavCircleCount()>0.750000) at "), "{text}");
    // Unchanged since HEAD: equivalent.
    git(repo, &["commit", "-qam", "two"]);
    let o = Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(["fpl", "diff", "--git", "HEAD", "with_procedure.xml"])
        .current_dir(repo)
        .output()
        .expect("runs");
    assert_eq!(code(&o), 0, "{}", stdout(&o));
}

#[test]
fn diff_usage_errors_exit_2() {
    assert_eq!(code(&vouch(&["fpl", "diff", "only_one.xml"])), 2);
    let d = demo().display().to_string();
    assert_eq!(code(&vouch(&["fpl", "diff", &d, "/nonexistent/plan.xml"])), 2);
}
