//! `cargo xtask bench instructions [--mesh PATH] [--top N]`: the instructions the release
//! `algesurf smooth` executes on the benchmark mesh, counted by valgrind's cachegrind, in
//! total and for the functions that execute the most.
//!
//! Why: on a shared or virtualised machine wall times move by a third from one hour to the
//! next (`docs/PERFORMANCE.md`, fourteenth pass), so a change of a few per cent cannot be seen
//! in seconds. A function's instruction count does not depend on the load: the same binary
//! gives the same count for most functions in every run, to the instruction; those whose work
//! depends on which thread takes which face (the split faces' per-thread plan caches) move by
//! a few thousand in hundreds of millions, and the whole run's total also counts the thread
//! pool's idle spinning. Instructions are not time (cache misses and
//! page faults are not in them), so wall-clock benchmarks stay the measure of record; this is
//! the measure for comparing two versions of a function.
//!
//! The run is the one `cargo xtask bench smooth` times: the same mesh, the resolution
//! estimated to give at least [`crate::bench_peers::TRIANGLES`] triangles, the PLY written to
//! `target/bench-smooth/`. The counts are written to
//! `target/bench-smooth/cachegrind.out` (for `cg_annotate` or `cg_diff` against another
//! version's). Needs `valgrind` and `cg_annotate` on the `PATH`; without them it says so and
//! does nothing. It runs about 30 times slower than the command (bunny: ~50 s).

use std::path::Path;
use std::process::Command;

use crate::Result;
use crate::bench_peers::{
    bench_dir, bench_mesh, build_release_cli, estimated_resolution, mesh_stem, obj_counts,
    release_cli,
};

/// Functions listed when `--top` is not given.
const DEFAULT_TOP: usize = 25;

/// `cargo xtask bench instructions [--mesh PATH] [--top N]`.
pub fn run(root: &Path, args: &[String]) -> Result<()> {
    let top = match args.iter().position(|a| a == "--top") {
        Some(i) => args
            .get(i + 1)
            .and_then(|v| v.parse::<usize>().ok())
            .ok_or("--top needs a number of functions")?,
        None => DEFAULT_TOP,
    };
    let mesh = bench_mesh(root, args)?;
    for tool in ["valgrind", "cg_annotate"] {
        if !on_path(tool) {
            println!("xtask: instruction counts skipped: `{tool}` is not on the PATH");
            return Ok(());
        }
    }
    build_release_cli(root)?;
    let (faces, edges) = obj_counts(&mesh)?;
    let (n, m) = estimated_resolution(faces, edges);
    let dir = bench_dir(root)?;
    let counts = dir.join("cachegrind.out");
    let _ = std::fs::remove_file(&counts);
    let stem = mesh_stem(&mesh);
    let exe = release_cli(root);
    let mut cmd = Command::new("valgrind");
    cmd.args(["--tool=cachegrind", "--cache-sim=no"])
        .arg(format!("--cachegrind-out-file={}", counts.display()))
        .arg(&exe)
        .arg("smooth")
        .arg(&mesh)
        .arg("-o")
        .arg(dir.join(format!("{stem}-instructions.ply")))
        .args(["--resolution", &n.to_string(), "--across", &m.to_string()]);
    eprintln!("xtask: running {cmd:?}");
    let out = cmd
        .output()
        .map_err(|e| format!("cannot start valgrind: {e}"))?;
    // Exit status 3: written, with missed rays or multiple roots (reported, still counted).
    if !out.status.success() && out.status.code() != Some(3) {
        eprint!("{}", String::from_utf8_lossy(&out.stderr));
        return Err(format!(
            "valgrind … algesurf smooth failed with {}",
            out.status
        ));
    }
    let mut annotate = Command::new("cg_annotate");
    annotate.arg(&counts);
    let annotated = annotate
        .output()
        .map_err(|e| format!("cannot start cg_annotate: {e}"))?;
    if !annotated.status.success() {
        return Err(format!(
            "cg_annotate {} failed with {}",
            counts.display(),
            annotated.status
        ));
    }
    let text = String::from_utf8_lossy(&annotated.stdout);
    let rows = count_rows(&text, top + 1);
    if rows.is_empty() {
        return Err(format!(
            "cg_annotate printed no counts for {}",
            counts.display()
        ));
    }
    println!(
        "algesurf smooth {} --resolution {n} --across {m}: instructions (cachegrind; {})",
        mesh.display(),
        counts.display()
    );
    for row in rows {
        println!("{row}");
    }
    Ok(())
}

/// Whether a file named `program` is in a directory of `PATH` (`cg_annotate` has no option
/// that exits with success, so it cannot be probed by running it).
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|path| {
        std::env::split_paths(&path).any(|dir| {
            dir.join(program).is_file()
                || dir
                    .join(format!("{program}{}", std::env::consts::EXE_SUFFIX))
                    .is_file()
        })
    })
}

/// The first `limit` count rows of `cg_annotate`'s output, in its order (the program total
/// first, then the functions by count): lines that start with a count such as
/// `1,266,243,788 ( 8.31%)`, trimmed. The per-line source annotations that follow the
/// function list start the same way, so only the rows before the first source section are
/// taken.
fn count_rows(text: &str, limit: usize) -> Vec<String> {
    let mut rows = Vec::new();
    for line in text.lines() {
        if line.starts_with("-- Auto-annotated source") || line.starts_with("-- User-annotated") {
            break;
        }
        let trimmed = line.trim_start();
        let count_len = trimmed
            .find(|c: char| !(c.is_ascii_digit() || c == ','))
            .unwrap_or(trimmed.len());
        let starts_with_count =
            count_len > 0 && trimmed[..count_len].chars().any(|c| c.is_ascii_digit());
        if starts_with_count && trimmed[count_len..].trim_start().starts_with('(') {
            rows.push(trimmed.to_string());
            if rows.len() == limit {
                break;
            }
        }
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::count_rows;

    /// The rows of a `cg_annotate` listing: the total and the functions in order, up to the
    /// limit, and nothing from the source annotations after them.
    #[test]
    fn count_rows_reads_the_total_and_the_function_list() {
        let text = "\
--------------------------------------------------------------------------------
Ir
--------------------------------------------------------------------------------
15,238,848,029 (100.0%)  PROGRAM TOTALS

--------------------------------------------------------------------------------
Ir                    file:function
--------------------------------------------------------------------------------
1,266,243,788 ( 8.31%)  ???:algesurf_hull::overlap::depth_until
  871,133,899 ( 5.72%)  ???:algesurf_mesh::morton::MortonBvh::slot_pairs::{{closure}}
  834,166,815 ( 5.47%)  ???:algesurf_apatch::constrained::plan::solve

--------------------------------------------------------------------------------
-- Auto-annotated source: /work/main/crates/hull/src/overlap.rs
--------------------------------------------------------------------------------
  276,924 ( 0.00%)      let (mut lo, mut hi) = (v[0], v[0]);
";
        let rows = count_rows(text, 3);
        assert_eq!(
            rows,
            vec![
                "15,238,848,029 (100.0%)  PROGRAM TOTALS",
                "1,266,243,788 ( 8.31%)  ???:algesurf_hull::overlap::depth_until",
                "871,133,899 ( 5.72%)  ???:algesurf_mesh::morton::MortonBvh::slot_pairs::{{closure}}",
            ]
        );
        assert_eq!(
            count_rows(text, 100).len(),
            4,
            "stops at the source section"
        );
        assert!(count_rows("no counts here\n", 5).is_empty());
    }
}
