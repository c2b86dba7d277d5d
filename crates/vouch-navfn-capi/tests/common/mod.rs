//! What the C program tests share: one program at a time, the cdylib's folder, a private build
//! folder, compiling `tests/c/*.c` with `cc`, running a program with input.
#![allow(dead_code, reason = "each test binary uses part of the helpers")]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The tests compile and run programs; one at a time, so that no test forks while another's
/// freshly linked program is being started (Linux answers that with "text file busy").
pub fn serial() -> std::sync::MutexGuard<'static, ()> {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    LOCK.lock().unwrap_or_else(|e| e.into_inner())
}

/// The folder holding the cdylib (`libvouch_navfn_c.so`) built with this test.
pub fn lib_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test path");
    let deps = exe.parent().expect("deps folder").to_path_buf();
    for dir in [deps.clone(), deps.parent().expect("profile folder").to_path_buf()] {
        if dir.join("libvouch_navfn_c.so").exists() || dir.join("libvouch_navfn_c.dylib").exists() {
            return dir;
        }
    }
    panic!("libvouch_navfn_c not found next to {}", exe.display());
}

/// The test process's private build directory (`tempfile`: fresh, mode 0700), so that no
/// program is run from a path another process could have planted or left behind.
pub fn build_dir() -> &'static Path {
    static DIR: std::sync::OnceLock<tempfile::TempDir> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        tempfile::Builder::new()
            .prefix("capi-")
            .tempdir_in(env!("CARGO_TARGET_TMPDIR"))
            .expect("temporary directory")
    })
    .path()
}

/// Compiles the C program `tests/c/NAME.c` against the header and the cdylib, once per test
/// process, strict C99 with every warning an error.
pub fn program(cc: &str, name: &str) -> PathBuf {
    static BUILT: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = build_dir().join(name);
    let mut built = BUILT.lock().unwrap_or_else(|e| e.into_inner());
    if built.iter().any(|b| b == name) {
        return out;
    }
    let lib = lib_dir();
    let o = Command::new(cc)
        .args(["-std=c99", "-O1", "-Wall", "-Wextra", "-Werror", "-pedantic", "-I"])
        .arg(crate_dir.join("include"))
        .arg(crate_dir.join(format!("tests/c/{name}.c")))
        .arg("-L")
        .arg(&lib)
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .args(["-lvouch_navfn_c", "-o"])
        .arg(&out)
        .output()
        .expect("cc runs");
    assert!(o.status.success(), "cc failed:\n{}", String::from_utf8_lossy(&o.stderr));
    built.push(name.to_string());
    out
}

pub fn run(prog: &Path, args: &[&str], stdin: &str) -> String {
    // `cargo test` puts the profile folder before `deps` on LD_LIBRARY_PATH, and that path
    // outranks the program's run path: the profile folder's copy of the library, refreshed only
    // by `cargo build`, would be loaded instead of the one built with this test
    let inherited = std::env::var_os("LD_LIBRARY_PATH").unwrap_or_default();
    let library_path =
        std::env::join_paths(std::iter::once(lib_dir()).chain(std::env::split_paths(&inherited)))
            .expect("library path");
    // a program just linked can be "busy" for a moment while another test's fork still holds
    // the linker's descriptor: try again briefly
    let mut tries = 0;
    let mut child = loop {
        let spawned = Command::new(prog)
            .args(args)
            .env("LD_LIBRARY_PATH", &library_path)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn();
        match spawned {
            Err(e) if e.kind() == std::io::ErrorKind::ExecutableFileBusy && tries < 50 => {
                tries += 1;
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            other => break other.expect("program starts"),
        }
    };
    child.stdin.take().expect("stdin").write_all(stdin.as_bytes()).expect("cases sent");
    let o = child.wait_with_output().expect("program ends");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout).expect("utf-8")
}
