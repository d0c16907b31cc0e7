//! Where commands write: stdout that a closed pipe does not break, and output folders checked
//! before any work is done.

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::Error;

/// Set once stdout's reader has gone (`magbench … | head`): later output is dropped.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Writes `text` to stdout. A closed pipe is not an error: the command goes on (a sweep keeps
/// running and writing its results) and prints nothing more.
pub fn emit(text: &str) -> Result<(), Error> {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        return Ok(());
    }
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {
            STDOUT_CLOSED.store(true, Ordering::Relaxed);
            Ok(())
        }
        Err(e) => Err(Error::Failed(format!("writing to stdout: {e}"))),
        Ok(()) => Ok(()),
    }
}

/// `println!` that survives a closed pipe (see [`emit`]); a failure to write stdout otherwise
/// ends the command with exit 1.
macro_rules! outln {
    () => { $crate::output::emit("\n")? };
    ($($arg:tt)*) => { $crate::output::emit(&format!("{}\n", format_args!($($arg)*)))? };
}

/// `print!` that survives a closed pipe (see [`emit`]).
macro_rules! out {
    ($($arg:tt)*) => { $crate::output::emit(&format!($($arg)*))? };
}

pub(crate) use {out, outln};

/// Makes sure `dir` (given by command-line `option`) is a folder magbench can write into,
/// creating it if needed; otherwise exit 2 naming the option, the path and why.
pub fn prepare_dir(dir: &Path, option: &str) -> Result<(), Error> {
    let bad = |reason: String| Error::arg(option, format!("{}: {reason}", dir.display()));
    if dir.exists() && !dir.is_dir() {
        return Err(bad("is a file, not a folder".into()));
    }
    if let Err(e) = std::fs::create_dir_all(dir) {
        let under_file = dir
            .ancestors()
            .skip(1)
            .find(|a| a.exists())
            .filter(|a| !a.is_dir());
        return Err(bad(match under_file {
            Some(f) => format!("cannot create the folder: {} is a file", f.display()),
            None => format!("cannot create the folder: {e}"),
        }));
    }
    let probe = dir.join(".magbench-write-test");
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(bad(format!("cannot write into it: {e}"))),
    }
}

/// Makes sure the folder that will hold `file` (given by `option`) exists and is writable.
pub fn prepare_file(file: &Path, option: &str) -> Result<(), Error> {
    if file.is_dir() {
        return Err(Error::arg(
            option,
            format!("{}: is a folder, not a file", file.display()),
        ));
    }
    match file.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(dir) => prepare_dir(dir, option),
        None => prepare_dir(Path::new("."), option),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_folders_are_checked_and_named() {
        let d = tempfile::tempdir().unwrap();
        let file = d.path().join("f");
        std::fs::write(&file, "x").unwrap();
        let e = prepare_dir(&file, "--out").unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("--out") && e.to_string().contains("is a file"));
        let e = prepare_dir(&file.join("sub"), "--out").unwrap_err();
        assert!(e.to_string().contains("is a file"), "{e}");
        assert!(prepare_dir(&d.path().join("new/deep"), "--out").is_ok());
        assert!(!d.path().join("new/deep/.magbench-write-test").exists());
    }
}
