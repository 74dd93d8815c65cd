//! Whatever PLY input parses must survive a write and read in every PLY encoding unchanged.
#![no_main]

use algesurf_io::{Format, WriteOptions, read_bytes, write_bytes};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(mesh) = read_bytes(data, Format::Ply) else { return };
    // NaN != NaN: compare only meshes whose floats are all numbers.
    if mesh.positions.iter().any(|p| p.is_nan()) {
        return;
    }
    for ascii in [false, true] {
        let options = WriteOptions { ascii, ..WriteOptions::default() };
        let Ok(bytes) = write_bytes(&mesh, Format::Ply, &options) else { return };
        let back = read_bytes(&bytes, Format::Ply).expect("our own PLY reads back");
        assert_eq!(back.positions, mesh.positions);
        assert_eq!(back.faces().collect::<Vec<_>>(), mesh.faces().collect::<Vec<_>>());
    }
});
