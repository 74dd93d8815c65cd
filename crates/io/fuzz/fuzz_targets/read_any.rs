//! Every reader on arbitrary bytes: must return Ok or Err, never panic, hang or exhaust memory.
#![no_main]

use algesurf_io::{Format, read_bytes};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for format in Format::ALL {
        let _ = read_bytes(data, format);
    }
    let _ = Format::sniff(data);
});
