//! The layout's rules, read from the source (docs/architecture.md): the library's top-level
//! modules form layers, each importing only the layers below it; the planners are used through
//! their trait; no library file grows past the size a reader can hold.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The layers of the library from the bottom up: a module may import only modules of a lower
/// layer (or its own).
const LAYERS: [&str; 11] =
    ["scalar", "numerics", "model", "dynamics", "error", "plan", "planners", "analysis", "track", "report", "cli"];

/// Concrete planners and their own entry points: the CLI and the report use planners only
/// through `planners::planner` and the `Planner` trait.
const CONCRETE: [&str; 6] =
    ["NormalFormPlanner", "EcsaPlanner", "OptimalPlanner", "plan_with_motion", "plan_with_solution", "NfaMotion"];

/// Largest number of lines of a library file.
const MAX_LINES: usize = 550;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("readable src") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The source of a file without its comments and its test code (a `tests.rs` file, or what
/// follows `#[cfg(test)]`, which by house style closes a file).
fn code(path: &Path) -> String {
    if path.file_name().is_some_and(|n| n == "tests.rs") {
        return String::new();
    }
    let text = std::fs::read_to_string(path).expect("readable source");
    let text = text.split("#[cfg(test)]").next().unwrap_or_default();
    text.lines().map(|l| l.split("//").next().unwrap_or_default()).collect::<Vec<_>>().join("\n")
}

/// The top-level module of a file under `src/`, `None` for `lib.rs` and `main.rs`.
fn module_of(src: &Path, path: &Path) -> Option<String> {
    let rel = path.strip_prefix(src).expect("under src");
    let first = rel.components().next()?.as_os_str().to_str()?.to_string();
    match first.as_str() {
        "lib.rs" | "main.rs" => None,
        name => Some(name.trim_end_matches(".rs").to_string()),
    }
}

/// The items that `lib.rs` re-exports at the crate root, each with the module it comes from.
fn root_items(src: &Path) -> BTreeMap<String, String> {
    let lib = std::fs::read_to_string(src.join("lib.rs")).expect("lib.rs");
    let mut items = BTreeMap::new();
    for statement in lib.split(';') {
        let Some(path) = statement.trim().strip_prefix("pub use ") else { continue };
        let module = path.split("::").next().unwrap_or_default().to_string();
        let names = path.rsplit("::").next().unwrap_or_default();
        for name in names.trim_matches(|c| c == '{' || c == '}').split(',') {
            items.insert(name.trim().to_string(), module.clone());
        }
    }
    items
}

/// Top-level modules named by `crate::NAME` (in the library) or `freefloat::NAME` (in the CLI),
/// also inside `crate::{A, b::C}` lists; a root re-export counts as its module.
fn imports(code: &str, prefix: &str, roots: &BTreeMap<String, String>) -> Vec<String> {
    let ident = |s: &str| s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect::<String>();
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find(prefix) {
        rest = &rest[i + prefix.len()..];
        let names: Vec<String> = match rest.strip_prefix('{') {
            Some(list) => list.split('}').next().unwrap_or_default().split(',').map(|n| ident(n.trim())).collect(),
            None => vec![ident(rest)],
        };
        for name in names.into_iter().filter(|n| !n.is_empty()) {
            out.push(roots.get(&name).cloned().unwrap_or(name));
        }
    }
    out
}

fn layer(name: &str) -> usize {
    LAYERS.iter().position(|l| *l == name).unwrap_or_else(|| panic!("module `{name}` is in no layer of LAYERS"))
}

/// Every import goes down the layers: no circle, the model, numerics and dynamics know no
/// planner, report or CLI, numerics knows nothing of the robot, and only the CLI imports the
/// report.
#[test]
fn imports_go_down_the_layers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let roots = root_items(&src);
    assert!(roots.contains_key("Planner") && roots.contains_key("Scalar"), "lib.rs re-exports not found");
    let mut edges: BTreeMap<(String, String), PathBuf> = BTreeMap::new();
    for path in &files {
        let Some(module) = module_of(&src, path) else { continue };
        let code = code(path);
        let prefix = if module == "cli" { "freefloat::" } else { "crate::" };
        for target in imports(&code, prefix, &roots) {
            if target != module && LAYERS.contains(&target.as_str()) {
                edges.entry((module.clone(), target)).or_insert_with(|| path.clone());
            }
        }
    }
    assert!(!edges.is_empty(), "no imports found: the scan is broken");
    let upward: Vec<String> = edges
        .iter()
        .filter(|((from, to), _)| layer(to) >= layer(from))
        .map(|((from, to), path)| format!("{from} -> {to} ({})", path.display()))
        .collect();
    assert!(upward.is_empty(), "imports that go up or sideways the layers:\n{}", upward.join("\n"));
    for (from, to) in edges.keys() {
        if ["model", "numerics", "dynamics"].contains(&from.as_str()) {
            assert!(layer(to) < layer("error"), "{from} imports {to}");
        }
        if from == "numerics" {
            assert_eq!(to, "scalar", "numerics imports {to}: it must stay free of the robot");
        }
    }
}

/// The CLI and the report never name a concrete planner: they pick one by its method.
#[test]
fn planners_are_used_through_the_trait() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src.join("cli"), &mut files);
    rust_files(&src.join("report"), &mut files);
    for path in files {
        let code = code(&path);
        for name in CONCRETE {
            assert!(!code.contains(name), "{} names `{name}`: use `planners::planner(method, ..)`", path.display());
        }
    }
}

/// No library file is longer than [`MAX_LINES`].
#[test]
fn files_stay_short() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let long: Vec<String> = files
        .iter()
        .filter_map(|p| {
            let n = std::fs::read_to_string(p).expect("readable").lines().count();
            (n > MAX_LINES).then(|| format!("{} ({n} lines)", p.display()))
        })
        .collect();
    assert!(long.is_empty(), "files over {MAX_LINES} lines: {long:?}");
}

/// The binary never prints with `println!`, `print!`, `eprintln!` or `eprint!` (issue 24 item 6):
/// they panic on a closed or full stdout or stderr (`track | true`, `track > /dev/full`,
/// `2>/dev/full`). Output goes through `cli::emit` (checked), `cli::note` and
/// `cli::report_error` (stderr, failures ignored).
#[test]
fn the_binary_has_no_print_macros() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = vec![src.join("main.rs")];
    rust_files(&src.join("cli"), &mut files);
    assert!(files.len() > 5, "no CLI files found: the scan is broken");
    for path in files {
        let code = code(&path);
        for name in ["println!", "print!", "eprintln!", "eprint!"] {
            assert!(!code.contains(name), "{} uses `{name}`: write through `cli::emit` or `cli::note`", path.display());
        }
    }
}
