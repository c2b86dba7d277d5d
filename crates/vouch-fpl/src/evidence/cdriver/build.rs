//! Where the C side of the validation is built and run: the host (the system C compiler, the
//! driver as a process) or an emulated Cortex-M core (the ARM cross compiler with the flags of
//! a Paparazzi STM32 build, the driver on an MPS2 board of QEMU, talking over semihosting).
//!
//! The build directory is a fresh private temporary directory (`tempfile`: created with mode
//! 0700 under an unpredictable name, never reused), so no other user can plant or change the
//! program that is run.

use std::path::Path;
use std::process::{Command, Stdio};

use serde::Serialize;

use super::{DriverError, Limits, io_err};
use crate::evidence::cstate::Discovery;

/// The portable driver (see its header comment for the protocol).
pub const DRIVER_C: &str = include_str!("../c/explore_driver.c");
const PLATFORM_H: &str = include_str!("../c/vouch_platform.h");
const TEXT_H: &str = include_str!("../c/driver_text.h");
const VARS_H: &str = include_str!("../c/driver_vars.h");
const JOIN_H: &str = include_str!("../c/explore_join.h");
const ANSWERS_H: &str = include_str!("../c/driver_answers.h");
const HOST_RT_C: &str = include_str!("../c/host_rt.c");
const TARGET_RT_C: &str = include_str!("../c/target_rt.c");
const TARGET_LD: &str = include_str!("../c/target.ld");

/// The stub runtime's declarations: its globals are state variables too.
pub const RUNTIME_H: &str = include_str!("../../../tests/stub/include/fp_stub.h");

/// (relative path, contents) of the stub runtime files, embedded so that the `vouch` binary
/// validates without the source tree.
const STUB_FILES: &[(&str, &str)] = &[
    ("fp_stub.c", include_str!("../../../tests/stub/fp_stub.c")),
    ("include/fp_stub.h", RUNTIME_H),
    ("include/std.h", include_str!("../../../tests/stub/include/std.h")),
    ("include/autopilot.h", include_str!("../../../tests/stub/include/autopilot.h")),
    (
        "include/generated/modules.h",
        include_str!("../../../tests/stub/include/generated/modules.h"),
    ),
    ("include/modules/core/abi.h", include_str!("../../../tests/stub/include/modules/core/abi.h")),
];

/// The stub's own scripted oracle is renamed away; the driver defines the real one.
const RENAMES: [&str; 3] = [
    "-Dfp_cond=vouch_stub_fp_cond",
    "-Dfp_code=vouch_stub_fp_code",
    "-Dfp_value=vouch_stub_fp_value",
];

/// Where the compiled `auto_nav` runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Target {
    /// The system C compiler (`$CC`, else `cc`) and this machine.
    Host,
    /// A Cortex-M4F as on Paparazzi's STM32F4 autopilots: `arm-none-eabi-gcc`, QEMU's
    /// `mps2-an386` board.
    CortexM4,
    /// A Cortex-M7 as on the STM32F7 autopilots: QEMU's `mps2-an500` board.
    CortexM7,
}

/// The flags of a Paparazzi ChibiOS build for an STM32F4/F7 board after `-mcpu` (every flag
/// that changes the generated code; the warning flags are left out). Both boards use the same
/// ones: on the F7 the FPU options are ChibiOS's default, which the board file does not
/// override. Where each comes from, file and line at a given commit of Paparazzi, is in
/// `docs/fpl-evidence.md`.
const PAPARAZZI_STM32: &[&str] = &[
    "-O2",
    "-falign-functions=16",
    "-fomit-frame-pointer",
    "-ffunction-sections",
    "-fdata-sections",
    "-fno-common",
    "-mfloat-abi=hard",
    "-mfpu=fpv4-sp-d16",
    "-std=gnu99",
    "-mno-thumb-interwork",
    "-mthumb",
];

const HOST_FLAGS: &[&str] = &["-std=c99", "-O0"];

impl Target {
    /// Every target, host first.
    pub const ALL: [Target; 3] = [Target::Host, Target::CortexM4, Target::CortexM7];

    /// The name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Target::Host => "host",
            Target::CortexM4 => "cortex-m4",
            Target::CortexM7 => "cortex-m7",
        }
    }

    /// The target of a name (`host`, `cortex-m4`, `cortex-m7`).
    pub fn from_name(name: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == name)
    }

    /// The code-generation flags used unless `--cflags` replaces them.
    pub fn default_cflags(self) -> Vec<String> {
        let (cpu, flags) = match self {
            Target::Host => (None, HOST_FLAGS),
            Target::CortexM4 => (Some("-mcpu=cortex-m4"), PAPARAZZI_STM32),
            Target::CortexM7 => (Some("-mcpu=cortex-m7"), PAPARAZZI_STM32),
        };
        cpu.into_iter().chain(flags.iter().copied()).map(str::to_string).collect()
    }

    /// The C compiler: `$CC` or `cc` on the host, `$VOUCH_ARM_CC` or `arm-none-eabi-gcc`.
    pub fn compiler(self) -> String {
        let (var, default) = match self {
            Target::Host => ("CC", "cc"),
            _ => ("VOUCH_ARM_CC", "arm-none-eabi-gcc"),
        };
        std::env::var(var).unwrap_or_else(|_| default.to_string())
    }

    /// The emulator (`$VOUCH_QEMU_ARM` or `qemu-system-arm`) and its board, for the targets.
    pub fn emulator(self) -> Option<(String, &'static str)> {
        let board = match self {
            Target::Host => return None,
            Target::CortexM4 => "mps2-an386",
            Target::CortexM7 => "mps2-an500",
        };
        let qemu = std::env::var("VOUCH_QEMU_ARM").unwrap_or_else(|_| "qemu-system-arm".into());
        Some((qemu, board))
    }

    /// How the driver was built and where it ran, for reports.
    pub fn describe(self, cflags: &[String]) -> String {
        let run = match self.emulator() {
            Some((qemu, board)) => format!(", run by {qemu} -M {board}"),
            None => String::new(),
        };
        format!("{} ({} {}{run})", self.name(), self.compiler(), cflags.join(" "))
    }
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The C string literals that follow `FP_C(` and `FP_V(` in `header`, unescaped: the
/// conditions and values of the plan as the instrumented header carries them.
fn oracle_texts(header: &str) -> Vec<String> {
    let mut out = Vec::new();
    for opener in ["FP_C(\"", "FP_V(\""] {
        for (i, _) in header.match_indices(opener) {
            let mut text = String::new();
            let mut chars = header[i + opener.len()..].chars();
            while let Some(c) = chars.next() {
                match c {
                    '"' => break,
                    '\\' => text.extend(chars.next()),
                    _ => text.push(c),
                }
            }
            out.push(text);
        }
    }
    out
}

/// The decimal constants of the plan's comparisons (conditions and values of the header), as
/// the generated C writes them: the driver reads each back as its compiler made it, so that a build that rounds
/// them differently (e.g. `-fsingle-precision-constant`) shows.
pub fn comparison_constants(header: &str) -> Vec<String> {
    use crate::expr::{TokenKind, lex};
    let mut out: Vec<String> = Vec::new();
    for text in oracle_texts(header) {
        let Ok(tokens) = lex(&text) else { continue };
        let compares = tokens.iter().any(|t| {
            matches!(
                t.kind,
                TokenKind::Gt | TokenKind::Lt | TokenKind::Ge | TokenKind::Le | TokenKind::EqEq
            )
        });
        for t in tokens.iter().filter(|t| compares && matches!(t.kind, TokenKind::Float(_))) {
            let lit = &text[t.start..t.end];
            let plain =
                lit.chars().all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'));
            if plain && !out.iter().any(|o| o == lit) {
                out.push(lit.to_string());
            }
        }
    }
    out
}

/// The table of [`comparison_constants`] the driver is compiled with.
fn constants_header(constants: &[String]) -> String {
    let mut s = format!("#define VOUCH_N_CONSTS {}\n", constants.len());
    s.push_str("static const double vouch_consts[] = { 0");
    for c in constants {
        s.push_str(", ");
        s.push_str(c);
    }
    s.push_str(" };\n");
    s
}

/// Writes the sources of the driver into `dir`.
pub(super) fn write_sources(
    dir: &Path,
    discovery: &Discovery,
    constants: &[String],
) -> Result<(), DriverError> {
    std::fs::create_dir_all(dir.join("include/generated")).map_err(io_err("build dir"))?;
    std::fs::create_dir_all(dir.join("include/modules/core")).map_err(io_err("build dir"))?;
    let mut files: Vec<(&str, &str)> = STUB_FILES.to_vec();
    files.extend([
        ("flight_plan.h", discovery.registered_header.as_str()),
        ("vouch_runtime_vars.h", discovery.runtime_registrations.as_str()),
        ("explore_driver.c", DRIVER_C),
        ("vouch_platform.h", PLATFORM_H),
        ("driver_text.h", TEXT_H),
        ("driver_vars.h", VARS_H),
        ("explore_join.h", JOIN_H),
        ("driver_answers.h", ANSWERS_H),
        ("host_rt.c", HOST_RT_C),
        ("target_rt.c", TARGET_RT_C),
        ("target.ld", TARGET_LD),
    ]);
    let table = constants_header(constants);
    files.push(("vouch_consts.h", table.as_str()));
    let known: Vec<&str> = STUB_FILES.iter().map(|f| f.1).collect();
    let types = super::standins::standins(&discovery.registered_header, &known);
    files.push(("vouch_types.h", types.as_str()));
    for (rel, text) in files {
        std::fs::write(dir.join(rel), text).map_err(io_err(rel))?;
    }
    Ok(())
}

/// Compiles the driver in `dir` for `target` with `cflags`; `Ok(Err(log))` when the compiler
/// rejects the sources.
pub(super) fn compile(
    dir: &Path,
    target: Target,
    cflags: &[String],
) -> Result<Result<(), String>, DriverError> {
    let cc = target.compiler();
    let mut cmd = Command::new(&cc);
    cmd.current_dir(dir).args(cflags).args(["-w", "-Iinclude", "-I."]).args(RENAMES);
    // the stand-ins for the plan variables' types come before any source (`standins`)
    cmd.args(["-include", "vouch_types.h"]);
    match target {
        // everything resolved at start-up, the GOT read-only: the watched segment then holds
        // only the program's own static variables
        Target::Host => cmd.args(["-Wl,-z,relro,-z,now"]).args([
            "fp_stub.c",
            "explore_driver.c",
            "host_rt.c",
            "-o",
            "driver",
        ]),
        _ => cmd.args(["--specs=rdimon.specs", "-T", "target.ld"]).args([
            "fp_stub.c",
            "explore_driver.c",
            "target_rt.c",
            "-o",
            "driver.elf",
        ]),
    };
    let out = cmd.output().map_err(|source| DriverError::NoCompiler { cc, source })?;
    if out.status.success() {
        return Ok(Ok(()));
    }
    let msg = String::from_utf8_lossy(&out.stderr);
    Ok(Err(msg.lines().take(20).collect::<Vec<_>>().join("\n")))
}

/// The command that starts the compiled driver in `dir`, and the first request line when the
/// driver reads its limits from its input (the target has no command line).
pub(super) fn command(
    dir: &Path,
    target: Target,
    l: Limits,
) -> Result<(Command, Option<String>), DriverError> {
    let numbers = [l.leaf_budget as i64, l.question_limit as i64, l.values.0, l.values.1]
        .map(|n| n.to_string());
    let Some((qemu, board)) = target.emulator() else {
        let mut cmd = Command::new(dir.join("driver"));
        cmd.args(&numbers);
        return Ok((cmd, None));
    };
    let mut cmd = Command::new(&qemu);
    cmd.current_dir(dir)
        .args(["-M", board, "-nographic", "-monitor", "none", "-serial", "none", "-nic", "none"])
        .args(["-semihosting-config", "enable=on,target=native", "-kernel", "driver.elf"]);
    Ok((cmd, Some(format!("L {}", numbers.join(" ")))))
}

/// Whether the emulator can be started (for a clear error before the build).
pub(super) fn check_emulator(target: Target) -> Result<(), DriverError> {
    let Some((qemu, _)) = target.emulator() else { return Ok(()) };
    Command::new(&qemu)
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .map(|_| ())
        .map_err(|source| DriverError::NoEmulator { qemu, source })
}
