//! The architectural register file of one hardware thread.

/// One thread's registers: GPRs, FPU/MSA vector registers and the FPU/MSA control words.
///
/// The FPU runs with `Status.FR = 1`: FPU register `n` is the low 64 bits of `fpr[n]`;
/// a single-precision value lives in the low 32 bits. MSA vector register `wn` is all
/// 128 bits of `fpr[n]` (element 0 in the least significant bits).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RegFile {
    /// General-purpose registers; `gpr[0]` is always 0 (writes are discarded by the core).
    pub gpr: [u32; 32],
    /// FPU / MSA registers.
    pub fpr: [u128; 32],
    /// FPU control and status register (FCSR, `$31` of cp1).
    pub fcsr: u32,
    /// MSA control and status register (MSACSR).
    pub msacsr: u32,
}

/// FCSR value at reset: NaN-2008 and ABS-2008 set (read-only 1 in r6), round to nearest.
pub const FCSR_RESET: u32 = (1 << 18) | (1 << 19);

impl Default for RegFile {
    fn default() -> Self {
        RegFile {
            gpr: [0; 32],
            fpr: [0; 32],
            fcsr: FCSR_RESET,
            msacsr: 0,
        }
    }
}

impl RegFile {
    /// Reads FPU register `n` as a single (low 32 bits).
    ///
    /// One 32-bit load, the width of [`RegFile::set_f32_bits`]'s store: the optimiser
    /// may otherwise read `fpr[n] as u32` with a wider load, which cannot be forwarded
    /// from a just-written 32-bit store and stalls the interpreter (measured: the path
    /// tracer ran 35% slower in functional mode).
    #[inline(always)]
    pub fn f32_bits(&self, n: usize) -> u32 {
        let r = &self.fpr[n];
        #[cfg(target_endian = "little")]
        // SAFETY: `r` is a valid, borrowed `u128`; on a little-endian host its first 4
        // bytes are its low 32 bits, and `u32` needs no more alignment than `u128`.
        unsafe {
            *(r as *const u128 as *const u32)
        }
        #[cfg(not(target_endian = "little"))]
        {
            *r as u32
        }
    }

    /// Reads FPU register `n` as a double (low 64 bits; one 64-bit load, as
    /// [`RegFile::f32_bits`]).
    #[inline(always)]
    pub fn f64_bits(&self, n: usize) -> u64 {
        let r = &self.fpr[n];
        #[cfg(target_endian = "little")]
        // SAFETY: as in `f32_bits`, for the low 8 bytes.
        unsafe {
            *(r as *const u128 as *const u64)
        }
        #[cfg(not(target_endian = "little"))]
        {
            *r as u64
        }
    }

    /// Writes a single to FPU register `n`.
    ///
    /// The upper 32 bits of the FPU register become UNPREDICTABLE in the architecture;
    /// here they keep their previous value, like QEMU. Bits 64..128 (the MSA upper half)
    /// are also UNPREDICTABLE; here they are preserved.
    #[inline(always)]
    pub fn set_f32_bits(&mut self, n: usize, v: u32) {
        let r = &mut self.fpr[n];
        #[cfg(target_endian = "little")]
        // SAFETY: `r` is a valid, exclusively borrowed `u128`; on a little-endian host its
        // first 4 bytes are its low 32 bits, and `u32` needs no more alignment than `u128`.
        // (One 32-bit store: the masked 128-bit form compiles to two read-modify-writes.)
        unsafe {
            *(r as *mut u128 as *mut u32) = v
        };
        #[cfg(not(target_endian = "little"))]
        {
            *r = (*r & !0xFFFF_FFFFu128) | v as u128;
        }
    }

    /// Writes a double to FPU register `n` (the MSA upper half is preserved).
    #[inline(always)]
    pub fn set_f64_bits(&mut self, n: usize, v: u64) {
        let r = &mut self.fpr[n];
        #[cfg(target_endian = "little")]
        // SAFETY: as in `set_f32_bits`, for the low 8 bytes.
        unsafe {
            *(r as *mut u128 as *mut u64) = v
        };
        #[cfg(not(target_endian = "little"))]
        {
            *r = (*r & !(u64::MAX as u128)) | v as u128;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partial_fpr_accesses_touch_only_their_bits() {
        let mut r = RegFile::default();
        let all = 0x0123_4567_89AB_CDEF_FEDC_BA98_7654_3210u128;
        r.fpr[5] = all;
        assert_eq!(r.f32_bits(5), 0x7654_3210);
        assert_eq!(r.f64_bits(5), 0xFEDC_BA98_7654_3210);
        r.set_f32_bits(5, 0xDEAD_BEEF);
        assert_eq!(r.fpr[5], (all & !0xFFFF_FFFF) | 0xDEAD_BEEF);
        assert_eq!(r.f32_bits(5), 0xDEAD_BEEF);
        r.set_f64_bits(5, 0x1122_3344_5566_7788);
        assert_eq!(
            r.fpr[5],
            (all & !(u64::MAX as u128)) | 0x1122_3344_5566_7788
        );
        assert_eq!(r.f64_bits(5), 0x1122_3344_5566_7788);
        assert_eq!((r.fpr[4], r.fpr[6]), (0, 0));
    }
}
