//! The scalar FPU's control and status register: FCSR's Cause, Flags and Enables fields
//! and the trap on an enabled exception.
//!
//! The arithmetic itself is the soft-float core shared with MSA ([`crate::softfloat`]),
//! run in the environment [`Env::from_fcsr`] builds from FCSR (its rounding mode; FS is
//! ignored and subnormals are always computed exactly). Exception bits are the core's
//! `FLAG_*`, which FCSR holds shifted by 2 (Flags), 7 (Enables) and 12 (Cause).
//! `recip.fmt` and `rsqrt.fmt` are `1/x` and `1/sqrt(x)` with a rounding each (as QEMU
//! does), raising the steps' exceptions.
//!
//! [`Env::from_fcsr`]: crate::softfloat::Env::from_fcsr

const CAUSE_MASK: u32 = 0x3F << 12;

/// An enabled floating-point exception was raised (the instruction traps).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FpTrap {
    /// The cause bits (`softfloat::FLAG_*`).
    pub cause: u32,
}

/// Writes the cause field; traps if an enabled exception is raised, else accumulates flags.
#[inline(always)]
pub fn update(fcsr: &mut u32, exc: u32) -> Result<(), FpTrap> {
    // Branch-free on the common path: one store of cause and flags together.
    let f = (*fcsr & !CAUSE_MASK) | (exc << 12);
    if exc & (f >> 7) & 0x1F != 0 {
        *fcsr = f;
        return Err(FpTrap { cause: exc });
    }
    *fcsr = f | (exc << 2);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::softfloat::{FLAG_I, FLAG_V, FLAG_Z};

    #[test]
    fn update_sets_cause_accumulates_flags_and_traps_when_enabled() {
        let mut fcsr = 1 | (FLAG_Z << 2) | (FLAG_V << 12);
        assert_eq!(update(&mut fcsr, FLAG_I), Ok(()));
        assert_eq!(fcsr, 1 | ((FLAG_Z | FLAG_I) << 2) | (FLAG_I << 12));
        fcsr |= FLAG_V << 7;
        assert_eq!(
            update(&mut fcsr, FLAG_V | FLAG_I),
            Err(FpTrap {
                cause: FLAG_V | FLAG_I
            })
        );
        // The trap leaves the cause set and the flags as they were.
        assert_eq!((fcsr >> 12) & 0x3F, FLAG_V | FLAG_I);
        assert_eq!((fcsr >> 2) & 0x1F, FLAG_Z | FLAG_I);
    }
}
