//! Connects the MSA engine ([`crate::msa`]) to the core: memory access and fault mapping.

use crate::memory::{MemFault, Memory};
use crate::msa::{self, MsaFault, MsaInst, MsaMemory, MsaOutcome};
use crate::thread::{Fault, Shared, Thread};

/// MSA's view of a thread's memory (global memory plus its local store).
struct ThreadMem<'a> {
    mem: &'a mut Memory,
    local: &'a mut [u8],
}

impl MsaMemory for ThreadMem<'_> {
    type Error = MemFault;

    fn load(&mut self, addr: u32, buf: &mut [u8]) -> Result<(), MemFault> {
        if buf.len() == 16 && addr & 15 == 0 {
            buf.copy_from_slice(&self.mem.read::<16>(self.local, addr)?);
            return Ok(());
        }
        // MSA vector accesses need no alignment: go byte by byte.
        for (i, b) in buf.iter_mut().enumerate() {
            *b = self
                .mem
                .read::<1>(self.local, addr.wrapping_add(i as u32))?[0];
        }
        Ok(())
    }

    fn store(&mut self, addr: u32, data: &[u8]) -> Result<(), MemFault> {
        if data.len() == 16 && addr & 15 == 0 {
            let mut v = [0u8; 16];
            v.copy_from_slice(data);
            return self.mem.write::<16>(self.local, addr, v);
        }
        // All or nothing: check every byte before writing any.
        for i in 0..data.len() as u32 {
            self.mem.read::<1>(self.local, addr.wrapping_add(i))?;
        }
        for (i, b) in data.iter().enumerate() {
            self.mem
                .write::<1>(self.local, addr.wrapping_add(i as u32), [*b])?;
        }
        Ok(())
    }
}

/// Runs one MSA instruction: `Ok(None)` done, `Ok(Some(taken))` for an MSA branch.
#[inline(never)]
pub fn execute(t: &mut Thread, sh: &mut Shared, inst: &MsaInst) -> Result<Option<bool>, Fault> {
    let mut m = ThreadMem {
        mem: &mut sh.mem,
        local: &mut t.local,
    };
    match msa::execute(inst, &mut t.regs, &mut m) {
        MsaOutcome::Done => Ok(None),
        MsaOutcome::Branch(taken) => Ok(Some(taken)),
        MsaOutcome::Fault(MsaFault::Memory(f)) => Err(Fault::Memory {
            fault: f,
            fetch: false,
        }),
        MsaOutcome::Fault(MsaFault::FpException { cause }) => {
            Err(Fault::FpException { cause, msa: true })
        }
    }
}
