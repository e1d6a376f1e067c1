//! Files: the JSON plan report and the CSV trajectory (docs/spec.md §3),
//! all written atomically (temporary file, then rename).

use crate::model::InputError;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::error::Error;
use crate::plan::Trajectory;
pub use crate::report::plan_report::{EcsaReport, PlanReport};

/// The temporary files and directories of writes in progress, removed by
/// [`remove_temporaries`] (the binary's SIGINT/SIGTERM handler).
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn temporaries() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    // A poisoned list is still a list of paths.
    TEMPORARIES.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Creates a temporary file or directory with `create` and registers it until
/// [`forget_temporary`], both under the list's lock: the SIGINT/SIGTERM handler
/// ([`remove_temporaries`]) holds that lock while it removes, so no temporary is created after it
/// looked, and none once it has run ([`interrupted`]).
pub fn create_temporary<T>(path: &Path, create: impl FnOnce(&Path) -> std::io::Result<T>) -> std::io::Result<T> {
    let mut list = temporaries();
    if interrupted() {
        return Err(std::io::Error::new(std::io::ErrorKind::Interrupted, "interrupted by a signal"));
    }
    let made = create(path)?;
    list.push(path.to_path_buf());
    Ok(made)
}

/// Unregisters a temporary path (renamed into place or removed).
pub fn forget_temporary(path: &Path) {
    temporaries().retain(|p| p != path);
}

/// Removes every registered temporary file or directory: called on SIGINT/SIGTERM, so that an
/// interrupted run leaves neither a `.NAME.PID.tmp` file nor a half-written directory.
///
/// New temporaries are refused from then on ([`create_temporary`]); a file already open may still
/// be renamed inside a temporary directory while it goes (then `remove_dir_all` fails), so the
/// removal is retried until the path is gone (at most about a second).
pub fn remove_temporaries() {
    let mut list = temporaries();
    INTERRUPTED.store(true, std::sync::atomic::Ordering::SeqCst);
    for path in list.drain(..) {
        remove_path(&path);
    }
}

/// Removes a file or a directory with its contents, retrying while entries are renamed inside it.
fn remove_path(path: &Path) {
    for _attempt in 0..200 {
        let _gone = if path.is_dir() { std::fs::remove_dir_all(path) } else { std::fs::remove_file(path) };
        if std::fs::symlink_metadata(path).is_err() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

/// Runs `f` with the signal handler held off ([`remove_temporaries`] waits for it): for a few
/// renames that must all happen or none. An error if the process is already being interrupted.
pub fn uninterrupted<T>(f: impl FnOnce() -> T) -> std::io::Result<T> {
    let _list = temporaries();
    if interrupted() {
        return Err(std::io::Error::new(std::io::ErrorKind::Interrupted, "interrupted by a signal"));
    }
    Ok(f())
}

/// The most bytes of a file's name kept in its temporary's name: `.NAME.PID.tmpdir` then stays
/// within the 255 bytes of a file name (`NAME_MAX`) for any valid name.
const TEMPORARY_NAME_BYTES: usize = 200;

/// The name of the temporary file (`kind = "tmp"`) or directory (`"tmpdir"`) of this process
/// for the file `name`: `.NAME.PID.tmp`, `NAME` cut to 200 bytes (so that the name fits NAME_MAX).
pub fn temporary_name(name: &str, kind: &str) -> String {
    format!(".{}.{}.{kind}", cut_name(name), std::process::id())
}

fn cut_name(name: &str) -> &str {
    let mut end = name.len().min(TEMPORARY_NAME_BYTES);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    &name[..end]
}

/// Set by [`remove_temporaries`]: the process is being interrupted and writes no more files.
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether [`remove_temporaries`] has run (the process is being interrupted).
pub fn interrupted() -> bool {
    INTERRUPTED.load(std::sync::atomic::Ordering::SeqCst)
}

/// The directory of `path` (`.` for a bare file name) and its file name.
pub fn split_path(path: &Path) -> (PathBuf, String) {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    (dir, path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default())
}

/// Removes `.NAME.PID.tmp` files (and `.NAME.PID.tmpdir` directories) in `dir` left by a
/// process that no longer runs (killed by SIGKILL, which no handler sees). Only where `/proc`
/// tells which processes run; only this pattern, never anything else.
pub fn remove_stale_temporaries(dir: &Path, name: &str) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let prefix = format!(".{}.", cut_name(name));
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = file.strip_prefix(&prefix) else { continue };
        let Some(pid) = rest.strip_suffix(".tmp").or_else(|| rest.strip_suffix(".tmpdir")) else { continue };
        let Ok(pid) = pid.parse::<u32>() else { continue };
        if pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists() {
            let path = entry.path();
            let _gone = if path.is_dir() { std::fs::remove_dir_all(&path) } else { std::fs::remove_file(&path) };
        }
    }
}

/// Writes `bytes` to `path` atomically: a temporary file `.NAME.PID.tmp` beside it
/// ([`temporary_name`]), then a rename, so that a crash never leaves a half-written result. The
/// temporary file is removed on failure and on SIGINT/SIGTERM (see [`remove_temporaries`]);
/// stale ones of killed runs are removed first ([`remove_stale_temporaries`]). Only a regular
/// file is replaced: a directory, a device, a FIFO or a socket at `path` is refused
/// ([`check_writable`]), and a symbolic link is followed (its target is replaced, the link stays).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let io = |source| Error::from(InputError::Io { path: path.to_path_buf(), source });
    let target = output_target(path)?;
    let (dir, name) = split_path(&target);
    remove_stale_temporaries(&dir, &name);
    let tmp = dir.join(temporary_name(&name, "tmp"));
    let result = (|| {
        let mut f = create_temporary(&tmp, |p| std::fs::File::create(p))?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, &target)
    })();
    if result.is_err() {
        let _cleanup = std::fs::remove_file(&tmp);
    }
    forget_temporary(&tmp);
    result.map_err(io)
}

/// The file that writing `path` replaces: `path`, or the target of a symbolic link. An error
/// when that is something other than a regular file or nothing (a directory, a device, a FIFO,
/// a socket, a dangling link): freefloat replaces only regular files.
fn output_target(path: &Path) -> Result<PathBuf, Error> {
    let refuse = |what: &str| {
        Error::from(InputError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::other(format!(
                "{what}; freefloat writes only regular files: give the path of a new or a regular file"
            )),
        })
    };
    let target = match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(path.to_path_buf()),
        Err(source) => return Err(Error::from(InputError::Io { path: path.to_path_buf(), source })),
        Ok(meta) if meta.is_symlink() => {
            std::fs::canonicalize(path).map_err(|_| refuse("is a symbolic link to nothing"))?
        }
        Ok(_) => path.to_path_buf(),
    };
    match std::fs::metadata(&target) {
        Ok(meta) if meta.is_file() => Ok(target),
        Ok(meta) if meta.is_dir() => Err(refuse("is a directory")),
        Ok(_) => Err(refuse("is not a regular file (a device, a FIFO or a socket)")),
        Err(source) => Err(Error::from(InputError::Io { path: path.to_path_buf(), source })),
    }
}

/// Checks before any work that `path` can be written: it is nothing yet or a regular file (or a
/// link to one), and its directory exists, is a directory and takes a new file (probed by
/// creating and removing this process's temporary there). The write itself may still fail, e.g.
/// on a full disk; then it is reported as usual.
pub fn check_writable(path: &Path) -> Result<(), Error> {
    let target = output_target(path)?;
    let (dir, name) = split_path(&target);
    let fail = |source| Error::from(InputError::Io { path: path.to_path_buf(), source });
    match std::fs::metadata(&dir) {
        Ok(meta) if meta.is_dir() => {}
        Ok(_) => return Err(fail(std::io::Error::other(format!("{} is not a directory", dir.display())))),
        Err(source) => return Err(fail(source)),
    }
    let probe = dir.join(temporary_name(&name, "tmp"));
    create_temporary(&probe, |p| std::fs::File::create(p)).map_err(fail)?;
    let removed = std::fs::remove_file(&probe);
    forget_temporary(&probe);
    removed.map_err(fail)
}

/// The CSV header of docs/spec.md §3.
pub const CSV_HEADER: [&str; 23] = [
    "t", "phi", "theta1", "theta2", "dphi", "dtheta1", "dtheta2", "ddphi", "ddtheta1", "ddtheta2", "z1", "z2", "z3",
    "tau1", "tau2", "xb", "yb", "xe", "ye", "psie", "dxe", "dye", "dpsie",
];

/// The trajectory as CSV (docs/spec.md §3): one row per sample, SI units, radians, empty cells where a
/// column does not apply; the header [`CSV_HEADER`]. The writer of every arm,
/// [`crate::report::arm::rows_csv`], on the 2-link trajectory's rows.
pub fn trajectory_csv(trajectory: &Trajectory) -> Result<Vec<u8>, Error> {
    crate::report::arm::rows_csv(&crate::report::arm::TrajectoryRows::from_trajectory(trajectory))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_whole_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.json");
        write_atomic(&path, b"first").unwrap();
        write_atomic(&path, b"second").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"second");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        let e = write_atomic(&dir.path().join("no/such/dir/x.json"), b"x");
        assert!(matches!(e, Err(Error::Input(InputError::Io { .. }))));
    }

    /// The signal handler's routine removes registered temporaries (files and directories); stale ones of dead
    /// processes go at the next write of that name, others' files stay.
    #[test]
    fn temporaries_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let tmp = dir.path().join(".x.json.1.tmp");
        create_temporary(&tmp, |p| std::fs::write(p, b"half")).unwrap();
        assert!(temporaries().contains(&tmp));
        // What the handler does to each registered path (the handler itself would also stop
        // every later write of this test process).
        remove_path(&tmp);
        forget_temporary(&tmp);
        assert!(!tmp.exists() && !temporaries().contains(&tmp));
        let dir_tmp = dir.path().join(".d.1.tmpdir");
        create_temporary(&dir_tmp, |p| std::fs::create_dir(p)).unwrap();
        std::fs::write(dir_tmp.join("f"), b"x").unwrap();
        remove_path(&dir_tmp);
        forget_temporary(&dir_tmp);
        assert!(!dir_tmp.exists());
        let stale = dir.path().join(".y.json.999999999.tmp");
        let other = dir.path().join(".z.json.999999999.tmp");
        std::fs::write(&stale, b"half").unwrap();
        std::fs::write(&other, b"keep").unwrap();
        write_atomic(&dir.path().join("y.json"), b"whole").unwrap();
        assert!(other.exists());
        assert_eq!(stale.exists(), !Path::new("/proc/self").exists());
        assert!(check_writable(&dir.path().join("none/y.json")).is_err());
    }
}
