//! The STRaTA ray stream memory (thesis §3.1–3.2): an on-chip memory of fixed-size ray
//! records in per-buffer LIFO lists (one buffer per treelet), shared by every TM.
//!
//! A kernel writes a ray to the buffer of the treelet it must visit next ([`write`]),
//! then calls [`schedule`] when it is done with its TM's current buffer: that waits until
//! every live thread of its TM has called it too (the TM has drained), then the TM's
//! stream scheduler picks the buffer the TM works on next (chip config
//! `stream_memory.schedule`) and every thread of the TM gets its id. Threads then [`read`]
//! rays from that buffer until it is empty, and schedule again. When every buffer is empty
//! the TM waits for a ray to be written by another TM; when every live thread of the chip
//! waits with the memory empty, [`schedule`] returns `None` to all: the frame's stream work
//! is done.
//!
//! Each function is the TRaX instructions it names plus the loads and stores of the
//! record; `trax native` runs the same semantics on host threads (the runtime's
//! `streams.rs`, shared with the emulator). Writing to a full memory stops the program
//! (as on the machine: a fault naming the thread and source line).

use super::hw;
use super::layout;

/// Words of a ray record: 48-byte rays (origin and direction 24 bytes, ray state 20,
/// traversal stack 4; thesis §3.2.1).
pub const RECORD_WORDS: usize = layout::STREAM_RECORD_WORDS;

/// One ray record as the stream memory stores it.
pub type Record = [u32; RECORD_WORDS];

/// Rays the stream memory holds, all buffers together (`trax.strcap`).
pub fn capacity() -> u32 {
    hw::stream_capacity()
}

/// Ray buffers of the stream memory (stream ids `0..buffers()`; the scene header's
/// `stream_buffers`, from the chip config).
pub fn buffers() -> u32 {
    hw::load_u32(hw::hdr_stream_buffers())
}

/// Writes `rec` to buffer `buffer` (`trax.strwstart`, one `trax.strw` per word,
/// `trax.strwend`). It is read back before the rays written to that buffer earlier (LIFO).
pub fn write(buffer: u32, rec: &Record) {
    hw::stream_write_start(buffer);
    hw::stream_write_word(rec[0]);
    hw::stream_write_word(rec[1]);
    hw::stream_write_word(rec[2]);
    hw::stream_write_word(rec[3]);
    hw::stream_write_word(rec[4]);
    hw::stream_write_word(rec[5]);
    hw::stream_write_word(rec[6]);
    hw::stream_write_word(rec[7]);
    hw::stream_write_word(rec[8]);
    hw::stream_write_word(rec[9]);
    hw::stream_write_word(rec[10]);
    hw::stream_write_word(rec[11]);
    hw::stream_write_end();
}

/// Takes the newest ray of the TM's current buffer into `rec` (`trax.strrstart`; when
/// there is one, a `trax.strr` per word and `trax.strrend`). `false` when the buffer is
/// empty (`rec` unchanged): time to [`schedule`].
pub fn read(rec: &mut Record) -> bool {
    if hw::stream_read_start() == 0 {
        return false;
    }
    rec[0] = hw::stream_read_word();
    rec[1] = hw::stream_read_word();
    rec[2] = hw::stream_read_word();
    rec[3] = hw::stream_read_word();
    rec[4] = hw::stream_read_word();
    rec[5] = hw::stream_read_word();
    rec[6] = hw::stream_read_word();
    rec[7] = hw::stream_read_word();
    rec[8] = hw::stream_read_word();
    rec[9] = hw::stream_read_word();
    rec[10] = hw::stream_read_word();
    rec[11] = hw::stream_read_word();
    hw::stream_read_end();
    true
}

/// Done with the TM's current buffer: waits for the TM's other live threads, then returns
/// the buffer the TM works on next (`trax.strsched`), or `None` when every live thread of
/// the chip waits here with the stream memory empty (nothing can write another ray).
pub fn schedule() -> Option<u32> {
    let b = hw::stream_schedule();
    if b == u32::MAX {
        None
    } else {
        Some(b)
    }
}

/// Rays now in buffer `buffer` (`trax.strsize`; 0 for an id past the buffers).
pub fn size(buffer: u32) -> u32 {
    hw::stream_size(buffer)
}
