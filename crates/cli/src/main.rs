//! The `algesurf` command-line tool.
// `deny`, not `forbid`: two FFI calls in [`allocator`] set mimalloc's purge policy and switch
// transparent huge pages off, each for a measured share of `algesurf smooth`'s wall time (see
// there); everything else stays safe.
#![deny(unsafe_code)]

mod check;
mod continuity;
mod convert;
mod cpu;
mod deviation;
mod flat;
mod frame;
mod grid;
mod hints;
mod info;
mod interrupt;
mod memory;
mod normals_fallback;
mod numbering;
mod render;
mod smooth;
mod stage;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// mimalloc instead of the system allocator. Construction allocates and frees millions of small
/// buffers on two threads (coefficient vectors, root sets, per-face systems) and large ones per
/// refinement round; with glibc's malloc 15 % of `algesurf smooth` on the bunny was in
/// `malloc`/`free` and page faults (`perf record`, 2026-12-01). Safe code: the crate's
/// `GlobalAlloc` impl carries the `unsafe`. Tuned by [`allocator::keep_freed_pages`] and
/// [`allocator::no_transparent_huge_pages`]: see there for why.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

mod allocator {
    /// Tells mimalloc to keep the pages it has freed instead of handing them back to the
    /// kernel one second later (its default `purge_delay` of 1000 ms).
    ///
    /// Why: construction frees and reallocates hundreds of megabytes per refinement round and
    /// per stage. After a purge, every reuse of a page is a page fault that the kernel answers
    /// with a freshly zeroed page. With mimalloc's defaults, `clear_page_erms` was 26 % of all
    /// samples of `algesurf smooth` on the bunny (`perf record`, 2026-12-01), and system time
    /// was 2.7 s of a 6.1 s run. Building without transparent huge pages (mimalloc's
    /// `no_thp`: no `MADV_HUGEPAGE`, so a fault zeroes 4 KiB instead of 2 MiB) took that to
    /// 0.9–1.0 s; no purging took it to 0.5 s, and the wall time to 4.4–4.6 s
    /// (`/usr/bin/time`, resolution 3 × 2, two runs each). The cost is that the process's
    /// resident size stays at its peak, which is right for a command that exits when its job
    /// is done.
    ///
    /// Transparent huge pages are off (see [`no_transparent_huge_pages`]).
    ///
    /// Called first thing in `main`, before any thread exists. A user's own
    /// `MIMALLOC_PURGE_DELAY` in the environment wins: mimalloc reads it at start-up, and the
    /// value is set here only when none is given.
    pub(crate) fn keep_freed_pages() {
        if std::env::var_os("MIMALLOC_PURGE_DELAY").is_some() {
            return;
        }
        // `mi_option_purge_delay` of mimalloc v3's `mimalloc.h` is the member right before
        // `mi_option_use_numa_nodes` (= 16, which the Rust crate exports); the crate has no
        // constant of its own for it. Both crates are pinned (`=0.1.52`, `=0.1.49`), so the
        // numbering cannot move under us.
        const PURGE_DELAY: libmimalloc_sys::mi_option_t =
            libmimalloc_sys::mi_option_use_numa_nodes - 1;
        // SAFETY: `mi_option_set` takes two integers and only stores the second in mimalloc's
        // option table (an atomic write); it touches no caller memory. A negative delay means
        // "never purge" (mimalloc's `options.c`: `purge_delay`).
        #[allow(unsafe_code)]
        unsafe {
            libmimalloc_sys::mi_option_set(PURGE_DELAY, -1);
        }
    }

    /// Switches transparent huge pages off for this process (`prctl(PR_SET_THP_DISABLE)`),
    /// unless `MIMALLOC_ALLOW_THP` is set in the environment, in which case mimalloc does
    /// what that says.
    ///
    /// Why: mimalloc asks for huge pages on its arenas (`MADV_HUGEPAGE`), and on the
    /// virtualised machine this project is measured on a 2 MiB fault can cost far more than
    /// the 512 faults of 4 KiB it replaces: the hypervisor backs the guest's memory on first
    /// touch, and the small pages a process gets are mostly ones the guest has used before
    /// while a huge page needs 2 MiB of contiguous, often never-touched memory. Eleven
    /// alternating pairs of runs of the bunny at 3 × 2 (`MIMALLOC_ALLOW_THP=1` against `=0`,
    /// docs/PERFORMANCE.md, twenty-third pass): construction + tessellation 1.19–1.76 s
    /// (median 1.50) against 0.95–1.05 s (median 1.00), system time 0.78–1.88 s against
    /// 0.24–0.34 s; only in four pairs right after 16 GiB had been written to `/dev/shm` did
    /// huge pages draw level (0.88–1.12 against 0.90–1.08 s), and that lasted minutes. Small
    /// pages cost ~100 k more page faults (0.25 s of system time on two threads) on every
    /// run; huge pages cost nothing or up to 0.8 s, depending on what the host did earlier.
    ///
    /// The kernel's per-process flag overrides `MADV_HUGEPAGE` and the system-wide
    /// `transparent_hugepage=always`, so mimalloc's arenas, whenever they were mapped, get
    /// small pages. Called first thing in `main`; on systems other than Linux it does nothing.
    pub(crate) fn no_transparent_huge_pages() {
        if std::env::var_os("MIMALLOC_ALLOW_THP").is_some() {
            return;
        }
        #[cfg(target_os = "linux")]
        {
            // SAFETY: `prctl(PR_SET_THP_DISABLE, 1, 0, 0, 0)` takes integers only and sets a
            // flag on the calling process's memory map; it reads or writes no user memory.
            // Its result is ignored on purpose: a kernel without the flag (before Linux 3.15)
            // leaves huge pages as they were, which is slower at worst.
            #[allow(unsafe_code)]
            let _ = unsafe { libc::prctl(libc::PR_SET_THP_DISABLE, 1, 0, 0, 0) };
        }
    }
}

/// Smooth piecewise-polynomial surfaces in Bernstein–Bézier form.
#[derive(Parser, Debug)]
#[command(
    name = "algesurf",
    version,
    about,
    long_about = None,
    arg_required_else_help = true,
    after_help = "Ctrl-C stops any command cleanly (exit status 130; 143 for SIGTERM): an output \
file is written whole or not at all, and an existing one is left as it was."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Describe a mesh: counts, components, genus, validation findings and the repairs
    /// `convert --repair` would make.
    Info(info::InfoArgs),
    /// Convert a mesh between OBJ, PLY, STL, OFF, glTF and GLB, optionally repairing it.
    Convert(convert::ConvertArgs),
    /// Build a C1-smooth A-patch surface through a triangle mesh and its normals, tessellate
    /// it and write it (with no INPUT: a built-in icosahedron, which becomes the unit sphere,
    /// to smooth.glb).
    Smooth(smooth::SmoothArgs),
    /// Render a mesh (or with --smooth its A-patch surface) to PNG: shaded, isophotes, zebra,
    /// patches or curvature, from preset views or an explicit camera.
    Render(render::RenderArgs),
    /// Build the surface as `smooth` does and measure every property it must have
    /// (interpolation, C1, normal agreement, simple roots, watertightness, parameter margins);
    /// exit status 2 when one fails.
    Check(check::CheckArgs),
}

/// Writes a command's report to stdout. A closed pipe (`algesurf info big.ply | head`) is not
/// an error: the reader has what it wanted (Rust ignores `SIGPIPE`, so the write fails with
/// `BrokenPipe` instead of ending the process, and `println!` would panic on it).
///
/// # Errors
/// Any other failure to write.
pub(crate) fn print_stdout(text: &str) -> std::io::Result<()> {
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e),
        _ => Ok(()),
    }
}

/// Writes a message line to stderr, ignoring a failure: a warning or an error message must not
/// become a panic because stderr is a closed pipe (`algesurf smooth x.obj 2>&1 | head -1`),
/// which `eprintln!` would.
pub(crate) fn print_stderr(line: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

/// `Err` (the writer's own [`algesurf_io::IoError::UnknownFormat`], naming the file and the
/// extensions it knows) when `output`'s extension names no mesh format: checked before the
/// work, since the writer would find it only at the end.
pub(crate) fn known_format(output: &std::path::Path) -> Result<(), algesurf_io::IoError> {
    match algesurf_io::Format::from_path(output) {
        Some(_) => Ok(()),
        None => Err(algesurf_io::IoError::UnknownFormat {
            path: output.to_path_buf(),
        }),
    }
}

/// Reads a mesh for a command; a file with neither vertices nor faces is an error (the
/// lenient OBJ reader skips lines it does not know, so any text file reads as an empty OBJ).
pub(crate) fn read_mesh(
    path: &std::path::Path,
) -> Result<algesurf_mesh::PolygonMesh, Box<dyn std::error::Error>> {
    let mesh = algesurf_io::read(path)?;
    if mesh.vertex_count() == 0 && mesh.face_count() == 0 {
        return Err(format!(
            "{}: no vertices or faces found (not a mesh file?)",
            path.display()
        )
        .into());
    }
    Ok(mesh)
}

fn main() -> ExitCode {
    allocator::keep_freed_pages();
    allocator::no_transparent_huge_pages();
    interrupt::install();
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Info(a) => info::run(a).map(|()| ExitCode::SUCCESS),
        Command::Convert(a) => convert::run(a).map(|()| ExitCode::SUCCESS),
        Command::Smooth(a) => smooth::run(a),
        Command::Render(a) => render::run(a).map(|()| ExitCode::SUCCESS),
        Command::Check(a) => check::run(a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            // Stopped by Ctrl-C or SIGTERM (`interrupt`): said as such, with the shell's
            // status.
            if let Some(i) = e.downcast_ref::<interrupt::Interrupted>() {
                print_stderr(format_args!("algesurf: {i}"));
                return ExitCode::from(i.exit_status());
            }
            print_stderr(format_args!("algesurf: error: {e}"));
            ExitCode::FAILURE
        }
    }
}
