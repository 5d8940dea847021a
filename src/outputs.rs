//! The command line's output files (cli.md: no output file is left half-written), all or
//! nothing: every file of a run is written to a temporary name beside its target first, and
//! only when all are written are they renamed, so a run that fails (a report that cannot be
//! written, a full disk) leaves none of its new files. A temporary file is named
//! `.NAME.PID.tmp`; those a killed run left behind are removed by the next run that writes
//! NAME. Part of the `quadlay` binary (declared in `main.rs`), not of the library.

use super::{bad_input, Failure};
use std::path::{Path, PathBuf};

/// A file written under its temporary name, waiting for [`commit`].
pub struct Staged {
    tmp: PathBuf,
    target: PathBuf,
    /// The target as the user named it, for messages.
    path: String,
}

fn cannot_write(path: &str, e: std::io::Error) -> Failure {
    Failure { code: 1, message: format!("{path}: cannot write: {e}") }
}

/// `.NAME.PID.tmp` beside `target`.
fn temporary(target: &Path, pid: u32) -> PathBuf {
    let name = target.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    target.with_file_name(format!(".{name}.{pid}.tmp"))
}

/// Removes the temporary files of `target` that runs no longer alive left behind (killed
/// before they could rename or remove them). Where no `/proc` tells which processes are
/// alive, nothing is removed: the files' names say what they are.
fn remove_stale_temporaries(target: &Path) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let Some(name) = target.file_name().map(|n| n.to_string_lossy().into_owned()) else { return };
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let Ok(entries) = std::fs::read_dir(&dir) else { return };
    let prefix = format!(".{name}.");
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let pid = file.strip_prefix(&prefix).and_then(|rest| rest.strip_suffix(".tmp"));
        if let Some(pid) = pid.filter(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit())) {
            if pid != std::process::id().to_string() && !proc.join(pid).exists() {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// Writes every `(path, bytes)` under its temporary name. On the first failure the
/// temporary files already written are removed and the error returned.
pub fn stage(files: Vec<(String, Vec<u8>)>) -> Result<Vec<Staged>, Failure> {
    let mut staged = Vec::with_capacity(files.len());
    for (path, bytes) in files {
        let target = PathBuf::from(&path);
        remove_stale_temporaries(&target);
        let tmp = temporary(&target, std::process::id());
        if let Err(e) = std::fs::write(&tmp, &bytes) {
            let _ = std::fs::remove_file(&tmp);
            discard(staged);
            return Err(cannot_write(&path, e));
        }
        staged.push(Staged { tmp, target, path });
    }
    Ok(staged)
}

/// Removes staged files without renaming them.
pub fn discard(staged: Vec<Staged>) {
    for s in staged {
        let _ = std::fs::remove_file(&s.tmp);
    }
}

/// Renames every staged file to its target. A rename that fails (it does not, within one
/// directory, short of a vanished directory) removes the temporary files left.
pub fn commit(staged: Vec<Staged>) -> Result<(), Failure> {
    let mut rest = staged.into_iter();
    while let Some(s) = rest.next() {
        if let Err(e) = std::fs::rename(&s.tmp, &s.target) {
            let _ = std::fs::remove_file(&s.tmp);
            discard(rest.collect());
            return Err(cannot_write(&s.path, e));
        }
    }
    Ok(())
}

/// The file `path` names, as an absolute path without links, whether it exists or not
/// (then its directory's, joined with its name).
fn identity(path: &str) -> Option<PathBuf> {
    let p = Path::new(path);
    if let Ok(c) = std::fs::canonicalize(p) {
        return Some(c);
    }
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(std::fs::canonicalize(dir).ok()?.join(p.file_name()?))
}

/// Refuses outputs that name an input or each other: `--report` naming the `-o` file would
/// replace the quad mesh with the JSON, `-o` naming the input mesh would overwrite it.
/// `inputs` and `outputs` are (option, path) pairs.
///
/// # Errors
/// A bad-input [`Failure`] naming both options.
pub fn check_distinct(inputs: &[(&str, &str)], outputs: &[(&str, &str)]) -> Result<(), Failure> {
    let ids: Vec<Option<PathBuf>> = outputs.iter().map(|(_, p)| identity(p)).collect();
    for (k, (option, path)) in outputs.iter().enumerate() {
        let Some(id) = &ids[k] else { continue };
        for (what, input) in inputs {
            if identity(input).as_ref() == Some(id) {
                return Err(bad_input(format!("{path}: {option} names {what}; it would be overwritten")));
            }
        }
        for (j, (other, _)) in outputs.iter().enumerate().take(k) {
            if ids[j].as_ref() == Some(id) {
                return Err(bad_input(format!("{path}: {option} and {other} name the same file; give each its own")));
            }
        }
    }
    Ok(())
}

/// Whether standard output is open. A program started with it closed (`quadlay ... >&-`)
/// finds `/dev/null` there: Rust's runtime opens it read-write in place of a closed standard
/// descriptor, so writes succeed and `--report -` would be lost without a word. A shell's
/// `> /dev/null` opens it write-only: that is the user's choice and counts as open.
#[cfg(target_os = "linux")]
pub fn stdout_is_open() -> bool {
    const O_ACCMODE: u32 = 0o3;
    const O_RDWR: u32 = 0o2;
    let target = std::fs::read_link("/proc/self/fd/1");
    let Ok(info) = std::fs::read_to_string("/proc/self/fdinfo/1") else { return target.is_ok() };
    let flags = info
        .lines()
        .find_map(|l| l.strip_prefix("flags:"))
        .and_then(|f| u32::from_str_radix(f.trim(), 8).ok());
    let reopened = target.is_ok_and(|t| t == Path::new("/dev/null")) && flags.is_some_and(|f| f & O_ACCMODE == O_RDWR);
    !reopened
}

#[cfg(not(target_os = "linux"))]
pub fn stdout_is_open() -> bool {
    true
}
