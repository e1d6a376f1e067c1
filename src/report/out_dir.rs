//! The output directory of `reproduce` (docs/spec.md §3): freefloat writes only into a
//! directory that does not exist yet, an empty one, or one it made itself (it holds the marker
//! file [`MARKER`], which lists the files written), and it never removes or replaces what it did
//! not write: a file is replaced only by name, atomically (a rename), and only when it is a
//! regular file.

use std::path::Path;

use crate::error::Error;
use crate::model::{InputError, excerpt};

/// The marker file in every directory that `reproduce` wrote: its first line says so, the
/// others name the files written, one a line.
pub const MARKER: &str = ".freefloat-out";

const MARKER_HEAD: &str = "# written by freefloat reproduce; the files it wrote:";

fn refused(path: &Path, what: String) -> Error {
    Error::from(InputError::Io { path: path.to_path_buf(), source: std::io::Error::other(what) })
}

/// Checks, before any work, that `reproduce` may write into `out`: it does not exist (it will be
/// created), or it is a directory that is empty or holds [`MARKER`]. Anything else (a file, a
/// device, a directory of other files) is bad input naming the path and what to do.
pub fn check_out_dir(out: &Path) -> Result<(), Error> {
    let meta = match std::fs::metadata(out) {
        Ok(meta) => meta,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(source) => return Err(Error::from(InputError::Io { path: out.to_path_buf(), source })),
    };
    if !meta.is_dir() {
        return Err(refused(
            out,
            "exists and is not a directory; give `--out` a new or an empty directory (nothing was changed)".into(),
        ));
    }
    let entries = std::fs::read_dir(out).map_err(|source| InputError::Io { path: out.to_path_buf(), source })?;
    let mut names = Vec::new();
    for entry in entries.flatten() {
        names.push(entry.file_name().to_string_lossy().into_owned());
        if names.len() > 3 {
            break;
        }
    }
    if names.is_empty() || std::fs::symlink_metadata(out.join(MARKER)).is_ok_and(|m| m.is_file()) {
        return Ok(());
    }
    names.sort();
    let shown = names.iter().take(3).map(|n| format!("`{}`", excerpt(n))).collect::<Vec<_>>().join(", ");
    Err(refused(
        out,
        format!(
            "is a directory that freefloat did not write (it holds {shown}{}, and no {MARKER}); give `--out` a new \
             or an empty directory (nothing was changed)",
            if names.len() > 3 { ", ..." } else { "" }
        ),
    ))
}

/// Moves every file of the directory `fresh` into `out` (created if missing) by name, each by
/// one rename, writes [`MARKER`] listing them, and removes the files the previous marker lists
/// that this run did not write (regular files only). A name at `out` that is not a regular file
/// (a directory, a link, a device) is refused before anything moves.
pub fn move_into(fresh: &Path, out: &Path) -> Result<usize, Error> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::from(InputError::Io { path, source })
    };
    check_out_dir(out)?;
    std::fs::create_dir_all(out).map_err(io(out))?;
    let mut names: Vec<String> = std::fs::read_dir(fresh)
        .map_err(io(fresh))?
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    for name in names.iter().map(String::as_str).chain([MARKER]) {
        let target = out.join(name);
        if let Ok(meta) = std::fs::symlink_metadata(&target)
            && !meta.is_file()
        {
            return Err(refused(&target, "is not a regular file: freefloat replaces only the files it writes".into()));
        }
    }
    let previous = std::fs::read_to_string(out.join(MARKER)).unwrap_or_default();
    let marker = names.iter().fold(format!("{MARKER_HEAD}\n"), |text, name| text + name + "\n");
    std::fs::write(fresh.join(MARKER), marker).map_err(io(fresh))?;
    for name in names.iter().map(String::as_str).chain([MARKER]) {
        std::fs::rename(fresh.join(name), out.join(name)).map_err(io(&out.join(name)))?;
    }
    let listed = previous.lines().skip_while(|l| l.starts_with('#'));
    for stale in listed.filter(|n| !n.is_empty() && !n.contains(['/', '\\']) && !n.starts_with('.')) {
        let path = out.join(stale);
        if !names.iter().any(|n| n == stale) && std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
            std::fs::remove_file(&path).map_err(io(&path))?;
        }
    }
    Ok(names.len())
}
