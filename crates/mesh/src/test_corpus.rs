//! The folder of real test meshes named by `ALGESURF_CORPUS`, for the workspace's corpus
//! tests: one reading of the variable, with one rule for relative paths. Compiled with the
//! `test-util` feature (which the other crates' dev-dependencies turn on); not part of the
//! public API.
//!
//! Cargo runs each test binary in its own crate's directory, not where `cargo test` was
//! typed, so a relative `ALGESURF_CORPUS` (the README's `../shared/data`) would name a
//! different folder in every crate. A relative path is therefore taken from the workspace
//! root, where the README runs the tests.

use std::path::{Path, PathBuf};

/// The workspace root: two levels above this crate's manifest (`crates/mesh`).
fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `dir` as given when absolute, otherwise taken from the workspace root (`Path::join` keeps
/// an absolute argument as it is): the rule of [`corpus_dir`], for the benches, which read
/// the variable with their own default.
pub fn resolve(dir: &Path) -> PathBuf {
    workspace_root().join(dir)
}

/// The corpus folder (canonical), or `None` after printing "skipped: ALGESURF_CORPUS unset"
/// when the variable is not set. A relative path is taken from the workspace root.
///
/// # Panics
/// When the variable is set but names no folder: a corpus test asked to run must not pass by
/// reading nothing. The message names the variable's value and the folder it resolved to.
pub fn corpus_dir() -> Option<PathBuf> {
    let Some(given) = std::env::var_os("ALGESURF_CORPUS") else {
        println!("skipped: ALGESURF_CORPUS unset");
        return None;
    };
    let dir = resolve(Path::new(&given));
    assert!(
        dir.is_dir(),
        "ALGESURF_CORPUS={} names no folder (resolved to {}; a relative path is taken from \
         the workspace root)",
        Path::new(&given).display(),
        dir.display()
    );
    // The resolved path, without the `crates/mesh/../..` it was built from, for the tests'
    // messages; the folder exists, so canonicalising can only fail on a race with its removal.
    Some(std::fs::canonicalize(&dir).unwrap_or(dir))
}

/// The corpus's files, sorted by path, or `None` (with the "skipped" line) when
/// `ALGESURF_CORPUS` is unset.
///
/// # Panics
/// As [`corpus_dir`], and when the folder cannot be listed (the message names it).
pub fn corpus_files() -> Option<Vec<PathBuf>> {
    let dir = corpus_dir()?;
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list the corpus folder {}: {e}", dir.display()))
        .filter_map(|entry| entry.ok().map(|entry| entry.path()))
        .filter(|path| path.is_file())
        .collect();
    files.sort();
    Some(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_are_taken_from_the_workspace_root() {
        assert_eq!(
            resolve(Path::new("../shared/data")),
            workspace_root().join("../shared/data")
        );
        assert_eq!(resolve(Path::new("/abs/data")), Path::new("/abs/data"));
    }

    #[test]
    fn the_workspace_root_holds_the_workspace_manifest() {
        let manifest = std::fs::read_to_string(workspace_root().join("Cargo.toml")).unwrap();
        assert!(manifest.contains("[workspace]"));
    }
}
