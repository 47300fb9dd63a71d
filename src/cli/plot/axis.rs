//! Axes shared by every chart trax draws (`trax plot`, `trax converge`, `trax ladder`):
//! the scale (linear, log10 where the data spans decades, log2 for power-of-two sizes),
//! tick positions chosen here (so no two ticks read the same and every decade of a log
//! axis is labelled) and tick labels with SI or binary prefixes (`512 KiB`, `4 MiB`,
//! `20 k`, `5 µ`), never `7.00e5`.
//!
//! Data are drawn in the axis's own coordinate (`log2 v`, `log10 v` or `v`) on a plain
//! `f64` range whose key points are the ticks; [`Axis::label`] turns a coordinate back
//! into the value's text.

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;

/// An axis's coordinate for plotters: its range with exactly its ticks as key points
/// (labels come from the chart's formatter, [`Axis::label`]).
pub struct Ticked {
    inner: RangedCoordf64,
    ticks: Vec<f64>,
}

impl Ranged for Ticked {
    type ValueType = f64;
    type FormatOption = NoDefaultFormatting;
    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }
    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }
    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks.clone()
        }
    }
}

impl ValueFormatter<f64> for Ticked {
    fn format(v: &f64) -> String {
        v.to_string()
    }
}

/// How values map onto the axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// `v`.
    Linear,
    /// `log10 v` (values > 0).
    Log10,
    /// `log2 v` (values > 0; power-of-two sizes).
    Log2,
}

/// What the values count: prefixes follow it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// Bytes: binary prefixes (KiB, MiB, GiB).
    Bytes,
    /// Anything else: SI prefixes (k, M, G, m, µ, n) beyond 10^4 or below 10^-2.
    Number,
    /// Percentages: plain decimals (`0.001`, never `1 m`: a prefix on a percentage reads
    /// as a unit), scientific only beyond 10^-6..10^6.
    Percent,
}

/// One axis: scale, unit, the drawn range and the ticks, in axis coordinates.
#[derive(Clone, Debug)]
pub struct Axis {
    /// The scale.
    pub scale: Scale,
    /// The unit.
    pub unit: Unit,
    /// Drawn range (axis coordinates).
    pub range: std::ops::Range<f64>,
    /// Tick positions (axis coordinates), ascending.
    pub ticks: Vec<f64>,
}

/// Values spanning at least this ratio get a log axis by default.
pub const LOG_SPAN: f64 = 100.0;

impl Axis {
    /// The axis for `values` (non-finite ones ignored). `log`: `Some(true)` asks for a log
    /// axis (refused, with an error, for values <= 0), `Some(false)` for a linear one,
    /// `None` chooses: log2 for byte sizes that are all powers of two (two or more of them),
    /// log10 for positive values spanning [`LOG_SPAN`] or more, else linear. `zero`: a
    /// linear axis starts at 0 (bars, counts). `pad`: fraction of the span added each side.
    pub fn fit(
        values: &[f64],
        unit: Unit,
        log: Option<bool>,
        zero: bool,
        pad: f64,
    ) -> Result<Axis, String> {
        let v: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        let (lo, hi) = v
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(*x), b.max(*x)));
        let (lo, hi) = if v.is_empty() { (0.0, 1.0) } else { (lo, hi) };
        let positive = !v.is_empty() && lo > 0.0;
        let pow2 = v.iter().all(|x| x.log2().fract() == 0.0);
        let scale = match log {
            Some(true) if !positive => {
                return Err(format!(
                    "a log axis needs values above 0 (the data go down to {lo})"
                ))
            }
            Some(true) if unit == Unit::Bytes && pow2 => Scale::Log2,
            Some(true) => Scale::Log10,
            Some(false) => Scale::Linear,
            None if positive && unit == Unit::Bytes && pow2 && hi / lo >= 2.0 => Scale::Log2,
            None if positive && hi / lo >= LOG_SPAN => Scale::Log10,
            None => Scale::Linear,
        };
        let mut axis = Axis {
            scale,
            unit,
            range: 0.0..1.0,
            ticks: Vec::new(),
        };
        let (a, b) = (axis.to_axis(lo), axis.to_axis(hi));
        let (a, b) = if scale == Scale::Linear && zero {
            (a.min(0.0), b.max(0.0))
        } else {
            (a, b)
        };
        let span = if b > a {
            b - a
        } else if scale == Scale::Linear {
            a.abs().max(1.0)
        } else {
            1.0
        };
        let p = span * pad;
        let start = if scale == Scale::Linear && zero && a >= 0.0 {
            a
        } else {
            a - p
        };
        axis.range = start..(b + p).max(start + span * 0.01);
        axis.ticks = axis.make_ticks();
        Ok(axis)
    }

    /// The plotters coordinate: the range with the ticks as its key points.
    pub fn coord(&self) -> Ticked {
        Ticked {
            inner: self.range.clone().into(),
            ticks: self.ticks.clone(),
        }
    }

    /// A category axis: `n` categories at 0..n, each a tick.
    pub fn categories(n: usize) -> Axis {
        Axis {
            scale: Scale::Linear,
            unit: Unit::Number,
            range: -0.5..(n.max(1) as f64 - 0.5),
            ticks: (0..n).map(|i| i as f64).collect(),
        }
    }

    /// A value in axis coordinates.
    pub fn to_axis(&self, v: f64) -> f64 {
        match self.scale {
            Scale::Linear => v,
            Scale::Log10 => v.log10(),
            Scale::Log2 => v.log2(),
        }
    }

    /// The value at axis coordinate `t`.
    pub fn value(&self, t: f64) -> f64 {
        match self.scale {
            Scale::Linear => t,
            Scale::Log10 => 10f64.powf(t),
            Scale::Log2 => t.exp2(),
        }
    }

    fn make_ticks(&self) -> Vec<f64> {
        let (a, b) = (self.range.start, self.range.end);
        let mut t: Vec<f64> = match self.scale {
            Scale::Linear => {
                let raw = (b - a) / 6.0;
                let mag = 10f64.powf(raw.log10().floor());
                let step = if self.unit == Unit::Bytes && raw >= 1.0 {
                    // Byte counts step by powers of two (1 KiB, 2 KiB, ... not 1000 B).
                    2f64.powf(raw.log2().ceil())
                } else {
                    [1.0, 2.0, 5.0, 10.0]
                        .iter()
                        .map(|m| m * mag)
                        .find(|s| *s >= raw)
                        .unwrap_or(10.0 * mag)
                };
                let first = (a / step).ceil() as i64;
                let last = (b / step).floor() as i64;
                (first..=last).map(|k| k as f64 * step).collect()
            }
            Scale::Log2 => {
                let (first, last) = (a.ceil() as i64, b.floor() as i64);
                let every = ((last - first) / 10 + 1).max(1);
                (first..=last)
                    .filter(|k| (k - first) % every == 0)
                    .map(|k| k as f64)
                    .collect()
            }
            Scale::Log10 => {
                let (first, last) = (a.floor() as i64, b.ceil() as i64);
                let decades = last - first;
                // Few decades (as drawn, not as rounded out to whole decades: 0.4..9 is
                // 1.4): 1-2-5 in each; many: every decade (or every few).
                let subs: &[f64] = if b - a <= 2.5 {
                    &[1.0, 2.0, 5.0]
                } else {
                    &[1.0]
                };
                let every = (decades / 10 + 1).max(1);
                (first..=last)
                    .filter(|k| (k - first) % every == 0)
                    .flat_map(|k| subs.iter().map(move |m| (m * 10f64.powi(k as i32)).log10()))
                    .filter(|t| *t >= a - 1e-9 && *t <= b + 1e-9)
                    .collect()
            }
        };
        // Two ticks never read the same.
        t.dedup_by(|x, y| self.label(*x) == self.label(*y));
        t
    }

    /// The text of the tick at axis coordinate `t`.
    /// On a linear axis of numbers every tick takes the prefix of the axis's largest
    /// value (`0, 5 m, 10 m`, never `5 m` beside `0.01`).
    pub fn label(&self, t: f64) -> String {
        let v = self.value(t);
        if self.scale != Scale::Linear || self.unit != Unit::Number || v == 0.0 {
            return format_value(v, self.unit);
        }
        let big = self.range.start.abs().max(self.range.end.abs());
        match si_prefix(big) {
            Some((f, p)) => format!("{} {p}", digits3(v / f)),
            None if (1e-2..1e4).contains(&big) => digits3(v),
            None => format_value(v, self.unit),
        }
    }
}

/// The SI prefix for magnitude `a` outside the plain range 10^-2..10^4 (`None` inside
/// it, or beyond the prefixes).
fn si_prefix(a: f64) -> Option<(f64, &'static str)> {
    const SI: [(f64, &str); 7] = [
        (1e12, "T"),
        (1e9, "G"),
        (1e6, "M"),
        (1e3, "k"),
        (1e-3, "m"),
        (1e-6, "µ"),
        (1e-9, "n"),
    ];
    if (1e-2..1e4).contains(&a) {
        return None;
    }
    SI.iter().copied().find(|(f, _)| a >= *f * 0.9995)
}

/// `v` with three significant digits at most, trailing zeros dropped.
fn digits3(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let d = (2 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{v:.d$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A value as a person writes it: `512 KiB`, `4 MiB` for bytes; `25 k`, `3.2 M`, `5 µ`
/// (SI prefixes beyond 10^4 and below 10^-2), otherwise plain with three significant
/// digits.
pub fn format_value(v: f64, unit: Unit) -> String {
    let a = v.abs();
    if a == 0.0 || !v.is_finite() {
        return if v.is_finite() {
            "0".into()
        } else {
            v.to_string()
        };
    }
    match unit {
        Unit::Bytes if a >= 1024.0 => {
            let prefixes = ["KiB", "MiB", "GiB", "TiB"];
            let mut x = a;
            let mut i = 0;
            while x >= 1024.0 && i < prefixes.len() {
                x /= 1024.0;
                i += 1;
            }
            let sign = if v < 0.0 { "-" } else { "" };
            format!("{sign}{} {}", digits3(x), prefixes[i - 1])
        }
        Unit::Bytes => format!("{} B", digits3(v)),
        Unit::Number if (1e-2..1e4).contains(&a) => digits3(v),
        Unit::Percent if (1e-6..1e6).contains(&a) => digits3(v),
        Unit::Percent => format!("{v:.1e}"),
        Unit::Number => match si_prefix(a) {
            Some((f, p)) => format!("{} {p}", digits3(v / f)),
            None => format!("{v:.1e}"),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_read_with_prefixes() {
        assert_eq!(format_value(524288.0, Unit::Bytes), "512 KiB");
        assert_eq!(format_value(4194304.0, Unit::Bytes), "4 MiB");
        assert_eq!(format_value(700000.0, Unit::Number), "700 k");
        assert_eq!(format_value(0.005, Unit::Number), "5 m");
        assert_eq!(format_value(0.05, Unit::Number), "0.05");
        assert_eq!(format_value(1234.0, Unit::Number), "1234");
        assert_eq!(format_value(2.5e9, Unit::Number), "2.5 G");
        assert_eq!(format_value(0.001, Unit::Percent), "0.001");
        assert_eq!(format_value(0.25, Unit::Percent), "0.25");
        assert_eq!(format_value(100.0, Unit::Percent), "100");
    }

    /// A linear axis labels every tick with the prefix of its largest value: never `5 m`
    /// beside `0.01` (the stacked energy chart's axis once read 0, 5 m, 0.01, 0.015).
    #[test]
    fn linear_ticks_share_one_prefix() {
        let a = Axis::fit(&[0.0, 0.025], Unit::Number, Some(false), true, 0.08).unwrap();
        let labels: Vec<String> = a.ticks.iter().map(|t| a.label(*t)).collect();
        assert_eq!(labels, ["0", "0.005", "0.01", "0.015", "0.02", "0.025"]);
        let a = Axis::fit(&[0.0, 0.0042], Unit::Number, Some(false), true, 0.08).unwrap();
        let labels: Vec<String> = a.ticks.iter().map(|t| a.label(*t)).collect();
        assert!(
            labels.iter().skip(1).all(|l| l.ends_with(" m")),
            "{labels:?}"
        );
    }

    /// A linear byte axis steps by powers of two (no `1000 B` beside `1.95 KiB`).
    #[test]
    fn linear_byte_ticks_are_binary() {
        let a = Axis::fit(&[0.0, 5000.0], Unit::Bytes, Some(false), true, 0.0).unwrap();
        let labels: Vec<String> = a.ticks.iter().map(|t| a.label(*t)).collect();
        assert_eq!(labels, ["0", "1 KiB", "2 KiB", "3 KiB", "4 KiB"]);
    }

    /// Power-of-two sizes: a log2 axis with a tick per size, labelled in KiB/MiB.
    #[test]
    fn power_of_two_sizes_get_a_log2_axis() {
        let sizes = [131072.0, 262144.0, 524288.0, 1048576.0, 4194304.0];
        let a = Axis::fit(&sizes, Unit::Bytes, None, false, 0.05).unwrap();
        assert_eq!(a.scale, Scale::Log2);
        let labels: Vec<String> = a.ticks.iter().map(|t| a.label(*t)).collect();
        assert_eq!(
            labels,
            ["128 KiB", "256 KiB", "512 KiB", "1 MiB", "2 MiB", "4 MiB"]
        );
        // Two sizes (an L1 of 32 or 64 KiB): ticks at the sizes, not at 39.1 KiB, 48.8 KiB.
        let a = Axis::fit(&[32768.0, 65536.0], Unit::Bytes, None, false, 0.05).unwrap();
        let labels: Vec<String> = a.ticks.iter().map(|t| a.label(*t)).collect();
        assert_eq!(labels, ["32 KiB", "64 KiB"]);
    }

    /// Decades: a log10 axis, labelled below 0.1 too, no tick twice ("10" once).
    #[test]
    fn log_axes_label_every_decade_once() {
        let a = Axis::fit(&[0.004, 0.2, 9.0, 11.0], Unit::Number, None, false, 0.05).unwrap();
        assert_eq!(a.scale, Scale::Log10);
        let labels: Vec<String> = a.ticks.iter().map(|t| a.label(*t)).collect();
        for want in ["0.01", "0.1", "1", "10"] {
            assert_eq!(
                labels.iter().filter(|l| *l == want).count(),
                1,
                "{labels:?}"
            );
        }
        // Within two decades, 1-2-5 ticks, below 0.1 too.
        let a = Axis::fit(&[0.02, 0.9], Unit::Number, Some(true), false, 0.0).unwrap();
        let fine: Vec<String> = a.ticks.iter().map(|t| a.label(*t)).collect();
        assert_eq!(fine, ["0.02", "0.05", "0.1", "0.2", "0.5"], "{fine:?}");
        // Under two decades that round out to three (0.4..9: 0.1..10) still get 1-2-5.
        let a = Axis::fit(&[0.4, 9.0], Unit::Number, Some(true), false, 0.0).unwrap();
        let fine: Vec<String> = a.ticks.iter().map(|t| a.label(*t)).collect();
        assert_eq!(fine, ["0.5", "1", "2", "5"], "{fine:?}");
        let mut sorted = labels.clone();
        sorted.dedup();
        assert_eq!(sorted, labels);
        assert!(Axis::fit(&[0.0, 5.0], Unit::Number, Some(true), false, 0.0).is_err());
        let lin = Axis::fit(&[3.0, 7.0], Unit::Number, None, true, 0.05).unwrap();
        assert_eq!(lin.scale, Scale::Linear);
        assert_eq!(lin.range.start, 0.0);
    }
}
