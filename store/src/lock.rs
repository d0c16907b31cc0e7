//! The lock of a results folder: one `bench` or `merge` at a time writes it.
//!
//! The lock is an OS advisory lock (`flock`) on the file [`LOCK`] inside the folder, held for
//! the whole command. The OS releases it when the process ends, however it ends, so a lock
//! left by a killed process is simply taken by the next one. The file also holds who has the
//! lock (pid, host, start, command) for the message a second process prints; that text is
//! informative only, the OS lock decides.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

use fs4::TryLockError;
use magbench_env::InputError;
use serde::{Deserialize, Serialize};

/// The lock file of a results folder.
pub const LOCK: &str = ".magbench.lock";

/// The environment variable that, set to `1`, runs without the lock (file systems without
/// `flock`, e.g. Lustre mounted with `noflock`).
pub const NO_LOCK_ENV: &str = "MAGBENCH_NO_LOCK";

/// Who holds a folder's lock, as written in the lock file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Holder {
    /// Process id.
    pub pid: u32,
    /// Host name.
    pub host: String,
    /// When the lock was taken (RFC 3339, UTC).
    pub started: String,
    /// The command (`bench`, `merge`).
    pub command: String,
}

impl Holder {
    fn me(command: &str) -> Holder {
        Holder {
            pid: std::process::id(),
            host: crate::manifest::host().name,
            started: crate::manifest::now(),
            command: command.to_string(),
        }
    }

    fn describe(&self) -> String {
        format!(
            "magbench {} (pid {} on host {}, since {})",
            self.command, self.pid, self.host, self.started
        )
    }
}

/// A held lock of a results folder; dropping it releases the lock.
#[derive(Debug)]
pub struct DirLock {
    file: Option<File>,
    exclusive: bool,
}

impl Drop for DirLock {
    fn drop(&mut self) {
        if let (Some(f), true) = (&self.file, self.exclusive) {
            // an empty lock file says "nobody"; the OS lock goes with the file handle
            let _ = f.set_len(0);
        }
    }
}

fn read_holder(f: &mut File) -> Option<Holder> {
    let mut text = String::new();
    f.rewind().ok()?;
    f.take(4096).read_to_string(&mut text).ok()?;
    serde_json::from_str(&text).ok()
}

fn in_use(dir: &Path, option: &str, holder: Option<Holder>) -> crate::Error {
    let who = holder
        .map(|h| h.describe())
        .unwrap_or_else(|| "another magbench process (no details in the lock file yet)".into());
    crate::Error::Input(InputError::new(
        dir.display().to_string(),
        option,
        format!(
            "the results folder is in use by {who}: wait for it to end, or choose another folder"
        ),
    ))
}

fn no_flock(path: &Path, e: std::io::Error) -> crate::Error {
    crate::Error::Failed(format!(
        "{}: cannot lock the results folder: {e} (the file system may not support flock, \
         e.g. Lustre without `-o flock` or NFS with `nolock`: see docs/results.md; \
         {NO_LOCK_ENV}=1 runs without the lock, at your own risk)",
        path.display()
    ))
}

/// Takes the exclusive lock of the results folder `dir` (which must exist) for `command`, or
/// fails with exit 2 naming the folder and the holder's pid and host. `option` names the
/// command-line option that gave `dir` (for the message).
pub fn exclusive(dir: &Path, command: &str, option: &str) -> Result<DirLock, crate::Error> {
    if std::env::var(NO_LOCK_ENV).is_ok_and(|v| v == "1") {
        eprintln!(
            "warning: {NO_LOCK_ENV}=1: {} is not locked; make sure no other process writes it",
            dir.display()
        );
        return Ok(DirLock {
            file: None,
            exclusive: true,
        });
    }
    let path: PathBuf = dir.join(LOCK);
    let mut f = OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(&path)
        .map_err(|e| crate::Error::Failed(format!("{}: {e}", path.display())))?;
    match fs4::FileExt::try_lock(&f) {
        Ok(()) => {}
        Err(TryLockError::WouldBlock) => return Err(in_use(dir, option, read_holder(&mut f))),
        Err(TryLockError::Error(e)) => return Err(no_flock(&path, e)),
    }
    let me = Holder::me(command);
    if let Some(old) = read_holder(&mut f) {
        // the OS released its lock, so that process has ended (on this host), or the file
        // system does not share flock between hosts
        let why = if old.host == me.host {
            "which ended without releasing it (killed?)".to_string()
        } else {
            "on another host; if that process still runs, flock is not shared between hosts on \
             this file system (see docs/results.md)"
                .to_string()
        };
        eprintln!(
            "note: {}: taking over the lock of {}, {why}",
            dir.display(),
            old.describe()
        );
    }
    let text = serde_json::to_string(&me).map_err(|e| crate::Error::Failed(e.to_string()))? + "\n";
    let written = f
        .set_len(0)
        .and_then(|()| f.rewind())
        .and_then(|()| f.write_all(text.as_bytes()))
        .and_then(|()| f.sync_data());
    written.map_err(|e| crate::Error::Failed(format!("{}: {e}", path.display())))?;
    Ok(DirLock {
        file: Some(f),
        exclusive: true,
    })
}

/// Takes a shared lock of `dir` for reading it whole (`results verify`): fails with exit 2 if
/// a `bench` or `merge` holds it. A folder whose lock file cannot be opened (read-only, no
/// lock file) is read without a lock.
pub fn shared(dir: &Path, option: &str) -> Result<DirLock, crate::Error> {
    let path = dir.join(LOCK);
    let Ok(mut f) = File::open(&path) else {
        return Ok(DirLock {
            file: None,
            exclusive: false,
        });
    };
    match fs4::FileExt::try_lock_shared(&f) {
        Ok(()) => Ok(DirLock {
            file: Some(f),
            exclusive: false,
        }),
        Err(TryLockError::WouldBlock) => Err(in_use(dir, option, read_holder(&mut f))),
        Err(TryLockError::Error(e)) => Err(no_flock(&path, e)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_names_the_holder_and_a_released_lock_is_taken_again() {
        let dir = tempfile::tempdir().unwrap();
        let a = exclusive(dir.path(), "bench", "--out").unwrap();
        let e = exclusive(dir.path(), "merge", "--out").unwrap_err();
        assert_eq!(e.exit_code(), 2);
        let msg = e.to_string();
        assert!(
            msg.contains(&format!("pid {}", std::process::id())),
            "{msg}"
        );
        assert!(msg.contains(&crate::manifest::host().name), "{msg}");
        assert!(msg.contains("magbench bench"), "{msg}");
        assert!(shared(dir.path(), "DIR").is_err());
        drop(a);
        let b = exclusive(dir.path(), "merge", "--out").unwrap();
        drop(b);
        assert!(shared(dir.path(), "DIR").is_ok());
    }
}
