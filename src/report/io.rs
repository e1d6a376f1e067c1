//! Files: the JSON plan report and the CSV trajectory (docs/spec.md §3),
//! all written atomically (temporary file, then rename).

use crate::model::InputError;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::Serialize;

use crate::error::Error;
use crate::plan::Trajectory;
use crate::planners::optimal::OptimalStats;
use crate::planners::{Details, Planned};
use crate::track::ClosedLoopCertificate;

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

/// The JSON report of a plan (docs/spec.md §3: every required key, radians inside).
#[derive(Debug, Clone, Serialize)]
pub struct PlanReport {
    /// `nfa` or `ecsa`.
    pub method: crate::plan::Method,
    /// Transformation (null for ECSA).
    pub transform: Option<crate::planners::nfa::normal_form::Transform>,
    /// `[a, b]` \[m\].
    pub mount: [f64; 2],
    /// Horizon \[s\].
    pub time: f64,
    /// Number of samples.
    pub samples: usize,
    /// Start `[phi, theta1, theta2]` \[rad\].
    pub start: [f64; 3],
    /// Goal \[rad\].
    pub goal: [f64; 3],
    /// Chained-form start (NFA only).
    pub z0: Option<[f64; 3]>,
    /// Chained-form goal (NFA only).
    pub zd: Option<[f64; 3]>,
    /// Verified final error of the velocity plan \[rad\].
    pub final_error: f64,
    /// Tolerance of the final error \[rad\].
    pub tolerance: f64,
    /// Whether every certificate holds (velocity level, and torque level with torques).
    pub certified: bool,
    /// `q(T)` reached by the verification \[rad\].
    pub reached: [f64; 3],
    /// Largest deviation of the verification from the planned path \[rad\].
    pub max_path_deviation: f64,
    /// The least clearance of the verified motion (issue 21; none without shapes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance: Option<crate::plan::clearance::ClearanceReport>,
    /// `[max|u1|, max|u2|]` \[rad/s\].
    pub max_abs_u: [f64; 2],
    /// Smallest `|sigma|` along the path.
    pub min_abs_sigma: f64,
    /// Smallest `|P|` along the path.
    pub min_abs_p: f64,
    /// `[max|tau1|, max|tau2|]` \[N m\] (with torques).
    pub max_abs_torque: Option<[f64; 2]>,
    /// Verified final error of the torque plan \[rad\] (with torques).
    pub torque_final_error: Option<f64>,
    /// The torque level (with torques): peaks, base-row check and the forward-dynamics
    /// certificate with its path deviation, angular momentum, integrator work and wall time.
    pub torque_certificate: Option<crate::plan::TorqueReport>,
    /// Wall time per stage \[s\].
    pub seconds: crate::plan::Seconds,
    /// ECSA iterations (null for NFA).
    pub iterations: Option<usize>,
    /// Chained-form steering of the NFA: `polynomial` (Sec. 5) or `band` (global normal form).
    pub steering: Option<&'static str>,
    /// The band steering's choice `(N, A, eps, kappa)`, when used.
    pub band: Option<crate::planners::nfa::steering::BandChoice>,
    /// Total variation of `(phi, theta1, theta2)` along the path \[rad\].
    pub joint_travel: [f64; 3],
    /// Control effort `integral_0^T |u|^2 dt` \[rad^2/s\].
    pub effort: f64,
    /// Accepted steps of the verification's integrator.
    pub verify_steps: usize,
    /// Joint velocities `[[u1(0), u2(0)], [u1(T), u2(T)]]` \[rad/s\]: zero for the NFA, not for
    /// the ECSA's plain trigonometric controls (docs/spec.md §6, item 8).
    pub controls_at_ends: [[f64; 2]; 2],
    /// ECSA details (ECSA only): basis, coefficients, residual history.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ecsa: Option<EcsaReport>,
    /// The minimum-effort planner's account (optimal only): effort, cost, residuals, SQP
    /// iterations, basis and the goal representative reached.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub optimal: Option<OptimalStats>,
    /// The closed-loop certificate (with torques): the nominal robot tracking the plan with
    /// computed torque at 1 kHz reaches the goal within 1e-6 rad.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closed_loop: Option<ClosedLoopCertificate>,
    /// The trajectory (only in `--out FILE.json`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trajectory: Option<Trajectory>,
}

impl PlanReport {
    /// The report of a planned motion (with its torque level, when computed), with the
    /// trajectory when `with_trajectory`.
    pub fn new(planned: &Planned, with_trajectory: bool) -> Self {
        let plan = &planned.plan;
        let p = &plan.problem;
        let nfa = match &planned.details {
            Details::Nfa(d) => Some(d),
            _ => None,
        };
        let v = &plan.verification;
        let mut report = Self {
            method: plan.method,
            transform: nfa.map(|d| d.transform),
            mount: [p.robot.mount.a, p.robot.mount.b],
            time: p.horizon,
            samples: plan.trajectory.t.len(),
            start: p.start.to_array(),
            goal: p.goal.to_array(),
            z0: nfa.map(|d| d.z0),
            zd: nfa.map(|d| d.zd),
            final_error: v.final_error,
            tolerance: v.tolerance,
            certified: v.certified && crate::plan::certificate::collision(v.clearance.as_ref()).is_ok(),
            reached: v.reached.to_array(),
            max_path_deviation: v.max_path_deviation,
            clearance: v.clearance,
            max_abs_u: plan.max_abs_u,
            min_abs_sigma: plan.min_abs_sigma,
            min_abs_p: plan.min_abs_p,
            max_abs_torque: None,
            torque_final_error: None,
            torque_certificate: None,
            seconds: plan.seconds,
            iterations: plan.iterations,
            steering: nfa.map(|d| if d.band.is_some() { "band" } else { "polynomial" }),
            band: nfa.and_then(|d| d.band),
            joint_travel: plan.joint_travel,
            effort: plan.effort,
            verify_steps: v.stats.accepted,
            controls_at_ends: controls_at_ends(&plan.trajectory),
            ecsa: None,
            optimal: match &planned.details {
                Details::Optimal(stats) => Some(*stats),
                _ => None,
            },
            closed_loop: None,
            trajectory: with_trajectory.then(|| plan.trajectory.clone()),
        };
        if let Details::Ecsa(solution) = &planned.details {
            report = report.with_ecsa(solution);
        }
        match &planned.torques {
            Some(torques) => report.with_torques(torques),
            None => report,
        }
    }
}

/// `[[u1(0), u2(0)], [u1(T), u2(T)]]` of a trajectory (zeros when it is empty).
fn controls_at_ends(trajectory: &Trajectory) -> [[f64; 2]; 2] {
    let u = |dq: Option<&[f64; 3]>| dq.map(|dq| [dq[1], dq[2]]).unwrap_or_default();
    [u(trajectory.dq.first()), u(trajectory.dq.last())]
}

/// The ECSA's part of the report (`"ecsa"` key of `plan --method ecsa --format json`).
#[derive(Debug, Clone, Serialize)]
pub struct EcsaReport {
    /// Harmonics `H` of the controls.
    pub harmonics: usize,
    /// `none` (the paper's plain series) or `sin2`.
    pub window: crate::planners::ecsa::Window,
    /// `c = (c_10, ..., c_1,2H, c_20, ..., c_2,2H)` \[rad/s\].
    pub coefficients: Vec<f64>,
    /// Final residual of the iteration \[rad\].
    pub residual: f64,
    /// Its tolerance \[rad\].
    pub residual_tolerance: f64,
    /// Residual before each update and after the last \[rad\].
    pub residual_history: Vec<f64>,
    /// Why the iteration stopped.
    pub termination: crate::planners::ecsa::Termination,
}

impl EcsaReport {
    /// The termination reason in words.
    pub fn termination_name(&self) -> String {
        self.termination.to_string()
    }
}

impl PlanReport {
    /// This report with the ECSA details of `solution`.
    fn with_ecsa(mut self, solution: &crate::planners::ecsa::EcsaSolution) -> Self {
        let s = &solution.stats;
        self.ecsa = Some(EcsaReport {
            harmonics: solution.basis.harmonics(),
            window: solution.basis.window(),
            coefficients: solution.coefficients.clone(),
            residual: s.residual,
            residual_tolerance: s.tolerance,
            residual_history: s.residual_history.clone(),
            termination: s.termination,
        });
        self
    }
}

impl PlanReport {
    /// This report with the closed-loop certificate (it does not change `certified`, which
    /// holds the open-loop levels).
    pub fn with_closed_loop(mut self, certificate: ClosedLoopCertificate) -> Self {
        self.closed_loop = Some(certificate);
        self
    }

    /// The report with the torque level filled in: `max_abs_torque`, `torque_final_error`,
    /// `seconds.torques`, the certificate; `certified` then requires both levels.
    fn with_torques(mut self, torques: &crate::plan::TorqueReport) -> Self {
        self.max_abs_torque = Some(torques.max_abs_torque);
        self.torque_final_error = Some(torques.certificate.final_error);
        self.certified &= torques.certificate.certified;
        self.seconds.torques = Some(torques.seconds.torques);
        self.torque_certificate = Some(*torques);
        self
    }
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
