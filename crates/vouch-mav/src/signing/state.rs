//! The signing replay state across restarts: a state file, written atomically, with the last
//! accepted timestamp of every stream and the highest timestamp known.
//!
//! **Guarantee.** A frame whose signature was accepted before the state was last written is
//! refused after a restart that reads the file back: its timestamp is not newer than its stream's
//! saved one. The state is written at least every second while it changes ([`StateSaver`]) and at
//! a clean shutdown, so after SIGINT/SIGTERM nothing accepted can be replayed, and after a crash
//! or power loss only frames accepted in the last second before it can (once each, and only while
//! their stream's sender has not yet sent anything newer through the restarted guard).
//! **Limit.** The file is the memory: deleting it, restoring an old copy, or giving another
//! `--signing-state` file forgets what was accepted (a new stream is then only held to the
//! one-minute rule of the signing specification). A file written for another key is refused.
//!
//! The write is atomic (a temporary file in the same folder, flushed to disk, then renamed over
//! the old one), so a crash during a write leaves the previous state, never a torn file.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use sha2::{Digest, Sha256};

use super::{ReplayState, SigningKey, Verifier};

/// How often the state is written while it changes.
pub const SAVE_INTERVAL: Duration = Duration::from_secs(1);
/// File name prefix of the default location.
const FILE_PREFIX: &str = "mav-signing-";
/// `format` field of the file.
const FORMAT: &str = "vouch-mav-signing-state";

/// Why the signing state could not be read or written.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum StateError {
    /// The file exists but cannot be read, or cannot be written.
    #[error("signing state {}: {source}", path.display())]
    #[diagnostic(code(mav::S001))]
    Io {
        /// The state file.
        path: PathBuf,
        /// Why.
        source: io::Error,
    },
    /// The file is not a signing state (damaged or something else).
    #[error("signing state {}: not a vouch signing state file ({why})", path.display())]
    #[diagnostic(
        code(mav::S002),
        help(
            "move it away to start without the saved replay state (frames accepted before can then be replayed)"
        )
    )]
    Damaged {
        /// The state file.
        path: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// The file was written for another signing key.
    #[error("signing state {} belongs to another signing key", path.display())]
    #[diagnostic(
        code(mav::S003),
        help("give each key its own state file (--signing-state), or move this one away")
    )]
    OtherKey {
        /// The state file.
        path: PathBuf,
    },
    /// No default location: none of STATE_DIRECTORY, XDG_STATE_HOME, HOME is set.
    #[error(
        "no place for the signing state: set --signing-state FILE (or STATE_DIRECTORY, XDG_STATE_HOME or HOME)"
    )]
    #[diagnostic(code(mav::S004))]
    NoDefault,
}

#[derive(serde::Serialize, serde::Deserialize)]
struct Saved {
    format: String,
    version: u32,
    /// Fingerprint of the key the state belongs to (not the key).
    key: String,
    local: u64,
    /// `[system id, component id, link id, last timestamp]`.
    streams: Vec<(u8, u8, u8, u64)>,
}

/// A short public fingerprint of a key (16 hex digits of SHA-256 over a label and the key): it
/// names and checks state files without revealing anything usable about the key.
pub fn key_fingerprint(key: &SigningKey) -> String {
    let mut h = Sha256::new();
    h.update(b"vouch-mav signing state\0");
    h.update(key.0);
    hex::encode(&h.finalize()[..8])
}

/// The default state file of a key: `mav-signing-<fingerprint>.json` in `$STATE_DIRECTORY`
/// (systemd's `StateDirectory=`), else `$XDG_STATE_HOME/vouch`, else `$HOME/.local/state/vouch`.
pub fn default_path(key: &SigningKey) -> Result<PathBuf, StateError> {
    let var = |n: &str| std::env::var_os(n).filter(|v| !v.is_empty()).map(PathBuf::from);
    let dir = var("STATE_DIRECTORY")
        .or_else(|| var("XDG_STATE_HOME").map(|d| d.join("vouch")))
        .or_else(|| var("HOME").map(|d| d.join(".local/state/vouch")))
        .ok_or(StateError::NoDefault)?;
    Ok(dir.join(format!("{FILE_PREFIX}{}.json", key_fingerprint(key))))
}

/// Reads the state saved for `key`; `Ok(None)` when there is no file yet (a first start).
pub fn load(path: &Path, key: &SigningKey) -> Result<Option<ReplayState>, StateError> {
    let text = match fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(source) => return Err(StateError::Io { path: path.into(), source }),
    };
    let damaged = |why: String| StateError::Damaged { path: path.into(), why };
    let saved: Saved = serde_json::from_str(&text).map_err(|e| damaged(e.to_string()))?;
    if saved.format != FORMAT || saved.version != 1 {
        return Err(damaged(format!("format {} version {}", saved.format, saved.version)));
    }
    if saved.key != key_fingerprint(key) {
        return Err(StateError::OtherKey { path: path.into() });
    }
    Ok(Some(ReplayState {
        streams: saved.streams.iter().map(|&(s, c, l, ts)| ((s, c, l), ts)).collect(),
        local: saved.local,
    }))
}

/// Writes the state atomically: a temporary file beside `path`, synced, renamed over it, and
/// the folder synced (so that the rename itself survives a power loss).
pub fn save(path: &Path, key: &SigningKey, state: &ReplayState) -> Result<(), StateError> {
    let saved = Saved {
        format: FORMAT.into(),
        version: 1,
        key: key_fingerprint(key),
        local: state.local,
        streams: state.streams.iter().map(|&((s, c, l), ts)| (s, c, l, ts)).collect(),
    };
    let io_err = |source| StateError::Io { path: path.into(), source };
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    fs::create_dir_all(dir).map_err(io_err)?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let text = serde_json::to_string(&saved).map_err(|e| io_err(io::Error::other(e)))?;
    let written = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()?;
        fs::rename(&tmp, path)?;
        // A folder can be opened and synced on Unix; elsewhere the rename is what there is.
        if let Ok(d) = fs::File::open(dir) {
            let _ = d.sync_all();
        }
        Ok(())
    })();
    if written.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    written.map_err(io_err)
}

/// A verifier with the replay state saved in `path` restored (a first start has none), after
/// checking that the file can be written: a guard that could not keep the state does not start.
pub fn resume(key: SigningKey, path: &Path) -> Result<Verifier, StateError> {
    let mut v = Verifier::new(key);
    if let Some(saved) = load(path, v.key())? {
        v.restore(&saved);
    }
    save(path, v.key(), &v.replay_state())?;
    Ok(v)
}

/// Writes a shared verifier's replay state to its file at least every [`SAVE_INTERVAL`] while it
/// changes (a thread of its own), and once more when finished.
pub struct StateSaver {
    verifier: Arc<Mutex<Verifier>>,
    path: PathBuf,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

fn lock(v: &Mutex<Verifier>) -> std::sync::MutexGuard<'_, Verifier> {
    v.lock().unwrap_or_else(|e| e.into_inner())
}

/// Saves if the state changed; the snapshot is taken under the lock, the file written outside.
fn save_changes(verifier: &Mutex<Verifier>, path: &Path) -> Result<(), StateError> {
    let (key, state) = {
        let mut v = lock(verifier);
        if !v.take_changes() {
            return Ok(());
        }
        (v.key().clone(), v.replay_state())
    };
    let r = save(path, &key, &state);
    if r.is_err() {
        // try again at the next interval
        lock(verifier).changed = true;
    }
    r
}

impl StateSaver {
    /// Starts saving `verifier`'s state to `path`; `on_error` is told about each failed write
    /// (the saver keeps trying every interval).
    pub fn start(
        verifier: Arc<Mutex<Verifier>>,
        path: PathBuf,
        on_error: impl Fn(&StateError) + Send + 'static,
    ) -> io::Result<StateSaver> {
        let stop = Arc::new(AtomicBool::new(false));
        let (v, p, s) = (verifier.clone(), path.clone(), stop.clone());
        let thread = std::thread::Builder::new().name("signing-state".into()).spawn(move || {
            let mut last = Instant::now();
            while !s.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(50));
                if last.elapsed() >= SAVE_INTERVAL {
                    last = Instant::now();
                    if let Err(e) = save_changes(&v, &p) {
                        on_error(&e);
                    }
                }
            }
        })?;
        Ok(StateSaver { verifier, path, stop, thread: Some(thread) })
    }

    /// Stops the thread and writes the state a last time (the clean-shutdown guarantee).
    pub fn finish(mut self) -> Result<(), StateError> {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        save_changes(&self.verifier, &self.path)
    }
}

impl Drop for StateSaver {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signing::{Signer, timestamp_now};

    fn key(b: u8) -> SigningKey {
        SigningKey([b; 32])
    }

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("vouch-signing-{tag}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        d
    }

    /// A signed frame of stream (255, 190, link) at timestamp `ts`.
    fn signed(k: &SigningKey, link: u8, ts: u64) -> Vec<u8> {
        // HEARTBEAT from 255/190 (GCS), unsigned, CRC_EXTRA 50
        let hb = crate::codec::encode::frame_v2_truncated(
            0,
            50,
            &[0, 0, 0, 0, 6, 8, 0, 0, 3],
            0,
            255,
            190,
        );
        let mut out = vec![];
        assert!(Signer::new(k.clone(), link).sign_into(&FrameRef::new(&hb).unwrap(), ts, &mut out));
        out
    }

    use crate::codec::FrameRef;

    #[test]
    fn accepted_frames_are_refused_after_a_restart() {
        let d = dir("restart");
        let path = d.join("state.json");
        let now = timestamp_now();
        let frames: Vec<Vec<u8>> = (0..3).map(|i| signed(&key(1), 2, now + i)).collect();
        let mut v = resume(key(1), &path).expect("first start");
        for f in &frames {
            assert_eq!(v.check(&FrameRef::new(f).unwrap(), now), Ok(()));
        }
        save(&path, v.key(), &v.replay_state()).unwrap();
        let mut again = resume(key(1), &path).expect("restart");
        for f in &frames {
            assert_eq!(
                again.check(&FrameRef::new(f).unwrap(), now),
                Err(super::super::SigReject::Replayed)
            );
        }
        // newer frames of the same stream, and other streams, still pass
        assert_eq!(again.check(&FrameRef::new(&signed(&key(1), 2, now + 9)).unwrap(), now), Ok(()));
        assert_eq!(again.check(&FrameRef::new(&signed(&key(1), 3, now)).unwrap(), now), Ok(()));
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn damaged_files_and_files_of_other_keys_are_refused() {
        let d = dir("refused");
        let path = d.join("state.json");
        resume(key(1), &path).expect("first start writes the file");
        assert!(matches!(resume(key(2), &path), Err(StateError::OtherKey { .. })));
        fs::write(&path, "{\"format\": 1").unwrap();
        let e = resume(key(1), &path).err().expect("damaged");
        assert!(matches!(e, StateError::Damaged { .. }), "{e}");
        // a folder that cannot hold the file: the guard would not start
        let blocked = d.join("file-not-dir");
        fs::write(&blocked, "x").unwrap();
        assert!(matches!(resume(key(1), &blocked.join("state.json")), Err(StateError::Io { .. })));
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn the_saver_writes_changes_within_a_second_and_at_the_end() {
        let d = dir("saver");
        let path = d.join("state.json");
        let v = Arc::new(Mutex::new(resume(key(1), &path).unwrap()));
        let saver = StateSaver::start(v.clone(), path.clone(), |_| {}).unwrap();
        let now = timestamp_now();
        assert_eq!(lock(&v).check(&FrameRef::new(&signed(&key(1), 2, now)).unwrap(), now), Ok(()));
        std::thread::sleep(SAVE_INTERVAL + Duration::from_millis(300));
        let saved = load(&path, &key(1)).unwrap().unwrap();
        assert_eq!(saved.streams, vec![((255, 190, 2), now)]);
        assert_eq!(
            lock(&v).check(&FrameRef::new(&signed(&key(1), 2, now + 5)).unwrap(), now),
            Ok(())
        );
        saver.finish().unwrap();
        assert_eq!(load(&path, &key(1)).unwrap().unwrap().streams, vec![((255, 190, 2), now + 5)]);
        // the atomic write leaves no temporary file behind
        let names: Vec<_> = fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names, vec![std::ffi::OsString::from("state.json")]);
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn the_default_location_follows_the_environment() {
        let k = key(1);
        let name = format!("mav-signing-{}.json", key_fingerprint(&k));
        assert_eq!(name.len(), "mav-signing-.json".len() + 16);
        assert_ne!(key_fingerprint(&k), key_fingerprint(&key(2)));
        // (the environment of a test process is shared: only read it here)
        if let Ok(p) = default_path(&k) {
            assert!(p.ends_with(&name), "{}", p.display());
        }
    }
}
