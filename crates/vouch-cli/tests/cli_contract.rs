//! The command line as a whole: every subcommand and argument documented with an example,
//! completions and man pages generated from the same tree, output safe to pipe into `head`.

use std::io::Read;
use std::process::{Command, Stdio};

use clap::CommandFactory;
use vouch_cli::Cli;

fn vouch() -> Command {
    Command::new(env!("CARGO_BIN_EXE_vouch"))
}

/// Every command below `cmd` (itself included), with its full name.
fn walk(cmd: &clap::Command, prefix: &str, out: &mut Vec<(String, clap::Command)>) {
    let name = if prefix.is_empty() {
        cmd.get_name().to_string()
    } else {
        format!("{prefix} {}", cmd.get_name())
    };
    out.push((name.clone(), cmd.clone()));
    // clap's generated `help` subcommands mirror the real tree; they are not commands of ours.
    for sub in cmd.get_subcommands().filter(|s| s.get_name() != "help") {
        walk(sub, &name, out);
    }
}

fn all_commands() -> Vec<(String, clap::Command)> {
    let mut cmd = Cli::command();
    cmd.build();
    let mut out = Vec::new();
    walk(&cmd, "", &mut out);
    out
}

#[test]
fn every_argument_has_help_text() {
    let mut missing = Vec::new();
    for (name, cmd) in all_commands() {
        for arg in cmd.get_arguments() {
            let id = arg.get_id().as_str();
            if matches!(id, "help" | "version") || arg.is_hide_set() {
                continue;
            }
            let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
            if help.trim().is_empty() {
                missing.push(format!("{name}: <{id}>"));
            }
        }
    }
    assert!(missing.is_empty(), "arguments without help text:\n{}", missing.join("\n"));
}

#[test]
fn every_subcommand_has_a_description_and_an_example() {
    let mut missing = Vec::new();
    for (name, cmd) in all_commands() {
        if cmd.get_about().is_none() {
            missing.push(format!("{name}: no description"));
        }
        let leaf = cmd.get_subcommands().next().is_none();
        let example = cmd.get_after_help().map(|h| h.to_string()).unwrap_or_default();
        if leaf && !example.contains("vouch ") {
            missing.push(format!("{name}: no example (after_help with a `vouch …` line)"));
        }
    }
    assert!(missing.is_empty(), "undocumented commands:\n{}", missing.join("\n"));
}

#[test]
fn json_is_always_a_switch() {
    let mut wrong = Vec::new();
    for (name, cmd) in all_commands() {
        for arg in cmd.get_arguments() {
            if arg.get_long() == Some("json") && arg.get_action().takes_values() {
                wrong.push(name.clone());
            }
        }
    }
    assert!(wrong.is_empty(), "--json takes a value in: {}", wrong.join(", "));
}

#[test]
fn completions_name_every_family_and_are_valid_bash() {
    let out = vouch().args(["completions", "bash"]).output().expect("vouch runs");
    assert!(out.status.success());
    let script = String::from_utf8(out.stdout).expect("utf-8");
    for word in ["fpl", "mav", "navfn", "compile", "guard", "campaign"] {
        assert!(script.contains(word), "completion script lacks {word}");
    }
    if let Some(bash) = vouch_testkit::program("bash", "--version") {
        let dir = tempfile::tempdir().expect("temp dir");
        let file = dir.path().join("vouch.bash");
        std::fs::write(&file, &script).expect("write");
        let check = Command::new(bash).arg("-n").arg(&file).status().expect("bash runs");
        assert!(check.success(), "bash -n rejects the completion script");
    }
    for shell in ["zsh", "fish", "elvish", "powershell"] {
        let out = vouch().args(["completions", shell]).output().expect("vouch runs");
        assert!(out.status.success() && !out.stdout.is_empty(), "{shell}");
    }
}

#[test]
fn man_pages_cover_every_command() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let dir = tmp.path().join("man");
    let status = vouch().args(["man", "-o"]).arg(&dir).status().expect("vouch runs");
    assert!(status.success());
    for (name, _) in all_commands() {
        let page = dir.join(format!("{}.1", name.replace(' ', "-")));
        let text =
            std::fs::read_to_string(&page).unwrap_or_else(|e| panic!("{}: {e}", page.display()));
        assert!(text.contains(".TH") && text.contains(".SH NAME"), "{}", page.display());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_reader_that_goes_away_ends_the_output_quietly() {
    let mut child = vouch()
        .args(["completions", "bash"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("vouch runs");
    drop(child.stdout.take());
    let status = child.wait().expect("vouch ends");
    let mut err = String::new();
    child.stderr.take().expect("stderr").read_to_string(&mut err).expect("stderr readable");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(status.code(), Some(0), "stderr: {err}");
}

/// A command line that does not parse is a usage error like any other: exit 2, the code of the
/// family it names (`vouch::C004` when none), in the `--message-format` asked for, and the
/// value it quotes escaped — an escape sequence typed or passed by a script never reaches the
/// terminal raw.
#[test]
fn command_lines_that_do_not_parse_are_coded_and_escaped() {
    let esc = "\u{1b}]0;retitled\u{7}";
    let cases: [(&[&str], &str); 5] = [
        (&["navfn", "bench", "--inflation", esc], "navfn::C004"),
        (&["fpl", "compile", "--no-such-option", "x.xml"], "fpl::C004"),
        (&["mav", "check"], "mav::C004"),
        (&["frobnicate"], "vouch::C004"),
        (&["--message-format", "short", "navfn", "plan", esc], "navfn::C004"),
    ];
    for (args, code) in cases {
        for format in ["human", "short", "json"] {
            let mut full = vec!["--message-format", format];
            full.extend_from_slice(args);
            let o = vouch().args(&full).output().expect("runs");
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{full:?}: {err}");
            assert!(err.contains(code), "{full:?}: {err}");
            assert!(!o.stderr.iter().any(|&b| b == 0x1b || b == 0x07), "raw control: {err:?}");
            if format == "json" {
                let line = err.lines().next().expect("a line");
                let v: serde_json::Value = serde_json::from_str(line).expect("JSON");
                assert_eq!(v["code"], code, "{line}");
            }
        }
    }
    // help and version still go to standard output with exit 0
    let o = vouch().args(["navfn", "--help"]).output().expect("runs");
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("Usage: vouch navfn"));
}
