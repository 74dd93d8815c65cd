//! Large files written as blocks of elements encoded in parallel and written out in order
//! (PLY's vertex and face lists, GLB's binary chunk), so that no copy of the whole file is
//! built in memory first.

use rayon::prelude::*;

/// Elements encoded as one piece of work: 16 Ki vertices of the `smooth` command's PLY
/// (doubles, normals, a patch id) are 850 KB, faces 340 KB; GLB's are 400 KB or less.
pub(crate) const BLOCK: usize = 1 << 14;

/// Blocks encoded at once per thread before they are written out, in order: enough to keep
/// both threads busy, little enough (~7 MB on two threads) to stay out of fresh pages. The
/// whole PLY was built in memory once: on the bunny's 1.46 M-triangle tessellation a 63 MB
/// buffer whose fresh pages took more of the `smooth` command's write stage than the encoding.
const BLOCKS_PER_THREAD: usize = 4;

/// Encodes elements `0..n` and writes them to `sink` in order: `fill(range, out)` appends
/// the bytes of the elements in `range` (at most [`BLOCK`] of them) to the empty `out`.
/// Blocks are encoded in parallel, so the bytes are those of one `fill(0..n, out)` whenever
/// `fill` encodes each element on its own (the same bytes for any split of the range).
pub(crate) fn write_blocks(
    n: usize,
    sink: &mut dyn std::io::Write,
    fill: &(dyn Fn(std::ops::Range<usize>, &mut Vec<u8>) + Sync),
) -> std::io::Result<()> {
    let blocks = n.div_ceil(BLOCK);
    let batch = (BLOCKS_PER_THREAD * rayon::current_num_threads()).max(1);
    let mut buffers: Vec<Vec<u8>> = vec![Vec::new(); batch.min(blocks)];
    let encode = |b: usize, buffer: &mut Vec<u8>| {
        buffer.clear();
        fill(b * BLOCK..((b + 1) * BLOCK).min(n), buffer);
    };
    for first in (0..blocks).step_by(batch) {
        let count = batch.min(blocks - first);
        if count == 1 {
            encode(first, &mut buffers[0]);
        } else {
            buffers[..count]
                .par_iter_mut()
                .enumerate()
                .for_each(|(k, buffer)| encode(first + k, buffer));
        }
        for buffer in &buffers[..count] {
            sink.write_all(buffer)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Blocks join in order: three blocks and a part, each element its own decimal line.
    #[test]
    fn blocks_are_written_in_element_order() {
        let n = 3 * BLOCK + 17;
        let mut out = Vec::new();
        write_blocks(n, &mut out, &|range, buf| {
            for i in range {
                buf.extend_from_slice(format!("{i}\n").as_bytes());
            }
        })
        .unwrap();
        let expected: String = (0..n).map(|i| format!("{i}\n")).collect();
        assert_eq!(String::from_utf8(out).unwrap(), expected);
        let mut empty = Vec::new();
        write_blocks(0, &mut empty, &|_, _| panic!("no block for no elements")).unwrap();
        assert!(empty.is_empty());
    }
}
