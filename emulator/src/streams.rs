//! The STRaTA ray stream memory, its overflow sentinel and the TMs' stream schedulers: the
//! exact semantics live in `trax_runtime::streams` (shared with `trax native`); this module
//! turns their errors into the faults a crash report names.

pub use trax_runtime::streams::*;

use crate::thread::Fault;

/// Buffer index of stream id `id`, or the fault of an id past the buffers.
pub fn buffer(m: &StreamMemory, id: u32) -> Result<usize, Fault> {
    m.buffer(id).ok_or(Fault::BadIndex {
        what: "ray stream",
        index: id,
    })
}

/// Pushes a ray onto buffer `b`; a full memory is [`Fault::StreamFull`], a full spill
/// area [`Fault::SpillAreaFull`].
pub fn push(m: &mut StreamMemory, b: usize, words: &[u32]) -> Result<Flow, Fault> {
    m.push(b, words).map_err(|e| match e {
        StreamError::Full(e) => Fault::StreamFull {
            stream: e.stream,
            capacity_rays: e.capacity_rays,
            ray_bytes: e.ray_bytes,
        },
        StreamError::SpillAreaFull(e) => Fault::SpillAreaFull {
            stream: e.stream,
            blocks: e.blocks,
            block_bytes: e.block_bytes,
        },
    })
}
