//! A DRAM timing value written either in DRAM clock cycles (`28`) or in nanoseconds (`"13.75ns"`).
//!
//! Nanoseconds are turned into cycles by [`ns_to_cycles`], the one rounding rule of the crate:
//! round up to whole cycles (as JEDEC does for nCK = tXX / tCK), with a 0.1% guard so that values
//! which are exact multiples of the clock period, written with rounded decimals, do not gain a cycle.

use serde::de::{self, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// A timing parameter: DRAM cycles or nanoseconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimeSpec {
    /// Whole DRAM command-clock cycles.
    Cycles(u32),
    /// Nanoseconds, converted with [`ns_to_cycles`] at the configured DRAM clock.
    Ns(f64),
}

impl TimeSpec {
    /// This value in DRAM cycles at `clock_mhz`.
    pub fn cycles(self, clock_mhz: u32) -> u32 {
        match self {
            TimeSpec::Cycles(c) => c,
            TimeSpec::Ns(ns) => ns_to_cycles(ns, clock_mhz),
        }
    }
}

/// Converts nanoseconds to DRAM cycles at `clock_mhz`: `ceil(ns * MHz / 1000)` with a 0.1% guard.
pub fn ns_to_cycles(ns: f64, clock_mhz: u32) -> u32 {
    let exact = ns * f64::from(clock_mhz) / 1000.0;
    let c = (exact * (1.0 - 1e-3)).ceil();
    if c <= 0.0 {
        0
    } else if c >= f64::from(u32::MAX) {
        u32::MAX
    } else {
        c as u32
    }
}

impl Serialize for TimeSpec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            TimeSpec::Cycles(c) => s.serialize_u32(c),
            TimeSpec::Ns(ns) => s.serialize_str(&format!("{ns}ns")),
        }
    }
}

struct TimeSpecVisitor;

impl Visitor<'_> for TimeSpecVisitor {
    type Value = TimeSpec;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(
            "a whole number of DRAM cycles (e.g. 28) or a duration string (e.g. \"13.75ns\")",
        )
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<TimeSpec, E> {
        u32::try_from(v)
            .map(TimeSpec::Cycles)
            .map_err(|_| E::custom(format!("cycle count {v} out of range 0..=4294967295")))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<TimeSpec, E> {
        u32::try_from(v)
            .map(TimeSpec::Cycles)
            .map_err(|_| E::custom(format!("cycle count {v} out of range 0..=4294967295")))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<TimeSpec, E> {
        let t = v.trim();
        let num = t
            .strip_suffix("ns")
            .ok_or_else(|| E::custom(format!("duration {v:?} must end in \"ns\"")))?
            .trim();
        match num.parse::<f64>() {
            Ok(ns) if ns.is_finite() && ns >= 0.0 => Ok(TimeSpec::Ns(ns)),
            _ => Err(E::custom(format!(
                "bad duration {v:?}: expected e.g. \"13.75ns\""
            ))),
        }
    }
}

impl<'de> Deserialize<'de> for TimeSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<TimeSpec, D::Error> {
        d.deserialize_any(TimeSpecVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding() {
        // DDR4-2400: tCK = 0.833 ns; 13.32 ns -> 16 cycles (JEDEC CL16 bin).
        assert_eq!(ns_to_cycles(13.32, 1200), 16);
        assert_eq!(ns_to_cycles(15.0, 1200), 18);
        assert_eq!(ns_to_cycles(14.0, 1000), 14);
        assert_eq!(ns_to_cycles(14.1, 1000), 15);
        assert_eq!(ns_to_cycles(0.0, 1000), 0);
    }
}
