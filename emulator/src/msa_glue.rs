//! Connects the MSA engine ([`crate::msa`]) to the core: memory access and fault mapping.

use crate::chip::Chip;
use crate::memory::MemFault;
use crate::msa::{self, MsaFault, MsaInst, MsaMemory, MsaOutcome};
use crate::thread::{Fault, Thread};

/// Why an MSA access did not complete.
enum MemExit {
    Fault(MemFault),
    /// A store to global memory the chip view may not write (nothing was written).
    Defer,
}

impl From<MemFault> for MemExit {
    fn from(f: MemFault) -> Self {
        MemExit::Fault(f)
    }
}

/// MSA's view of a thread's memory (global memory plus its local store).
struct ThreadMem<'a, C: Chip> {
    chip: &'a mut C,
    local: &'a mut [u8],
}

impl<C: Chip> MsaMemory for ThreadMem<'_, C> {
    type Error = MemExit;

    // MSA vector accesses are 16 bytes and need no alignment; the memory performs
    // misaligned accesses itself (byte-exact checks, stores all or nothing).
    fn load(&mut self, addr: u32, buf: &mut [u8]) -> Result<(), MemExit> {
        self.chip.note_load(addr);
        buf.copy_from_slice(&self.chip.shared().mem.read::<16>(self.local, addr)?);
        Ok(())
    }

    fn store(&mut self, addr: u32, data: &[u8]) -> Result<(), MemExit> {
        let mut v = [0u8; 16];
        v.copy_from_slice(data);
        match self.chip.store::<16>(self.local, addr, v)? {
            true => Ok(()),
            false => Err(MemExit::Defer),
        }
    }
}

/// How an MSA instruction ended.
pub enum MsaStep {
    /// Executed.
    Done,
    /// An MSA branch, taken or not.
    Branch(bool),
    /// Not executed: it stores to global memory the chip view may not write.
    Defer,
}

/// Runs one MSA instruction.
#[inline(never)]
pub fn execute<C: Chip>(t: &mut Thread, sh: &mut C, inst: &MsaInst) -> Result<MsaStep, Fault> {
    let mut m = ThreadMem {
        chip: sh,
        local: &mut t.local,
    };
    match msa::execute(inst, &mut t.regs, &mut m) {
        MsaOutcome::Done => Ok(MsaStep::Done),
        MsaOutcome::Branch(taken) => Ok(MsaStep::Branch(taken)),
        MsaOutcome::Fault(MsaFault::Memory(MemExit::Defer)) => Ok(MsaStep::Defer),
        MsaOutcome::Fault(MsaFault::Memory(MemExit::Fault(f))) => Err(Fault::Memory {
            fault: f,
            fetch: false,
        }),
        MsaOutcome::Fault(MsaFault::FpException { cause }) => {
            Err(Fault::FpException { cause, msa: true })
        }
    }
}
