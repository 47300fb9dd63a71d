//! Statistics declared once. A group of statistics (one object of the statistics
//! document, such as `timing` or `timing.stream`) is declared with [`stat_group!`]: per
//! field its Rust type, its document type, its meaning, and optionally its sweep column
//! (`results.csv`, `trax plot --y`), a label that prints it in the text summary, its axis
//! label as a series over time (`trax plot --over-time`), and the `docs/STATS.md` rows of
//! what is nested in it. From that one declaration come the struct (its field docs are
//! the meanings), its JSON (serde, in field order) and its [`Stat`] table; from the table
//! `docs/STATS.md`'s rows ([`md_rows`], checked against the committed file by
//! `tests/stats_json.rs` `stats_md_timing_section_is_generated`), the sweep's metrics
//! (`src/cli/sweep/metrics.rs` reads [`Stat::column`]), the summary's lines of labelled
//! statistics ([`summary_lines`]) and the over-time series (`Interval::series`).
//!
//! Adding a statistic to a group is one field in its declaration plus the line of
//! `stats::build` that computes it; `the_declaration_reaches_every_output` walks a
//! group declared in the test through every output.

use std::fmt::Write as _;

use serde_json::Value;

/// A statistic's sweep column.
#[derive(Clone, Copy, Debug)]
pub struct Column {
    /// Column name.
    pub name: &'static str,
    /// Axis label, without the unit.
    pub label: &'static str,
    /// Unit (empty: a count or a ratio).
    pub unit: &'static str,
}

/// One declared statistic.
#[derive(Clone, Copy, Debug)]
pub struct Stat {
    /// Its dotted path in the statistics document (`timing.fps`).
    pub path: &'static str,
    /// Its type in `docs/STATS.md` (`int`, `float`, `float?`, `object`, `map`).
    pub ty: &'static str,
    /// What it means (the field's doc and its `docs/STATS.md` row).
    pub doc: &'static str,
    /// Its sweep column, if it is one.
    pub column: Option<Column>,
    /// Its label in the text summary's lines of labelled statistics, if it has one there
    /// (the summary's older lines print the others in their own words).
    pub summary: Option<&'static str>,
    /// Its axis label in `trax plot --over-time`, if it is a series over time (a field of
    /// `timing.intervals[]`).
    pub series: Option<&'static str>,
    /// The statistics of the group it is (an object declared with [`stat_group!`]).
    pub nested: &'static [Stat],
    /// `docs/STATS.md` rows of what else is nested in it (given the statistic's path): an
    /// object's fields, a map's entries.
    pub rows: Option<fn(&str) -> String>,
}

impl Stat {
    /// A statistic with no column, summary label or nested rows.
    pub const PLAIN: Stat = Stat {
        path: "",
        ty: "",
        doc: "",
        column: None,
        summary: None,
        series: None,
        nested: &[],
        rows: None,
    };
}

/// `stats` and, after each, the statistics nested in it, depth first.
pub fn walk(stats: &'static [Stat]) -> Vec<&'static Stat> {
    let mut v = Vec::new();
    for st in stats {
        v.push(st);
        v.extend(walk(st.nested));
    }
    v
}

/// One `docs/STATS.md` table row.
pub fn md_row(path: &str, ty: &str, doc: &str) -> String {
    format!("| `{path}` | {ty} | {doc} |\n")
}

/// `docs/STATS.md` rows of `stats`: each statistic's row, then its nested rows.
pub fn md_rows(stats: &[Stat]) -> String {
    let mut s = String::new();
    for st in stats {
        s += &md_row(st.path, st.ty, st.doc);
        s += &md_rows(st.nested);
        if let Some(rows) = st.rows {
            s += &rows(st.path);
        }
    }
    s
}

/// The value at `path` (dotted, from the document's root) of `doc`, where `doc` is the
/// object at `root`.
pub fn value_at<'a>(doc: &'a Value, root: &str, path: &str) -> Option<&'a Value> {
    let rest = path.strip_prefix(root)?;
    rest.split('.')
        .filter(|k| !k.is_empty())
        .try_fold(doc, |v, k| v.get(k))
}

/// The summary lines of the labelled statistics of `stats` and those nested in them
/// (`label: value`), reading the values from `doc`, the JSON of the object at `root`.
pub fn summary_lines(stats: &'static [Stat], doc: &Value, root: &str) -> String {
    let mut s = String::new();
    for st in walk(stats) {
        if let (Some(label), Some(v)) = (st.summary, value_at(doc, root, st.path)) {
            let _ = writeln!(s, "{label}: {v}");
        }
    }
    s
}

/// Declares a group of statistics: a struct whose documented fields
/// (`field: Type => ("doc type", "meaning" [, column = (name, label, unit)]
/// [, summary = "label"] [, series = "axis label"] [, nested = { Group::STATS }]
/// [, rows = { fn }])`) are statistics at `PATH.field`, and whose other
/// fields (plain `field: Type`) are documented elsewhere or not part of the document
/// (`#[serde(skip)]`). `Self::STATS` lists the statistics in field order.
macro_rules! stat_group {
    ($(#[$sattr:meta])* pub struct $name:ident at $path:literal {
        $(
            $(#[$fattr:meta])*
            $field:ident: $ty:ty $(=> ($kind:literal, $doc:literal $(, $key:ident = $val:tt)*))?,
        )*
    }) => {
        $(#[$sattr])*
        pub struct $name {
            $( $(#[$fattr])* $(#[doc = $doc])? pub $field: $ty, )*
        }

        impl $name {
            /// The group's statistics, in field order.
            pub const STATS: &'static [$crate::timing::stat::Stat] = &[
                $( $( $crate::timing::stat::Stat {
                    path: concat!($path, ".", stringify!($field)),
                    ty: $kind,
                    doc: $doc,
                    $( $key: stat_group!(@$key $val), )*
                    ..$crate::timing::stat::Stat::PLAIN
                }, )? )*
            ];
        }
    };
    (@column ($n:literal, $l:literal, $u:literal)) => {
        Some($crate::timing::stat::Column { name: $n, label: $l, unit: $u })
    };
    (@summary $s:literal) => { Some($s) };
    (@series $s:literal) => { Some($s) };
    (@rows $f:expr) => { Some($f) };
    (@nested $g:expr) => { $g };
}
pub(crate) use stat_group;

#[cfg(test)]
mod tests {
    use serde::Serialize;

    use super::*;

    stat_group!(
        /// A group declared in the test: one statistic with every output.
        #[derive(Serialize)]
        pub struct Toy at "timing.toy" {
            toy_events: u64 => ("int", "toy events", column = ("toy_events", "Toy events", ""), summary = "toy events"),
            nested: Vec<u32> => ("array", "toy list", rows = { |p| md_row(&format!("{p}[]"), "int", "one toy") }),
            #[serde(skip)]
            hidden: u8,
        }
    );

    /// One field of the declaration: its JSON, its `docs/STATS.md` rows (nested ones
    /// too), its sweep column read from the JSON at its path, and its summary line.
    #[test]
    fn the_declaration_reaches_every_output() {
        let t = Toy {
            toy_events: 7,
            nested: vec![1],
            hidden: 3,
        };
        assert_eq!(t.hidden, 3);
        let json = serde_json::to_value(&t).unwrap();
        assert_eq!(json["toy_events"], 7);
        assert!(json.get("hidden").is_none());
        assert_eq!(
            md_rows(Toy::STATS),
            "| `timing.toy.toy_events` | int | toy events |\n\
             | `timing.toy.nested` | array | toy list |\n\
             | `timing.toy.nested[]` | int | one toy |\n"
        );
        let st = &Toy::STATS[0];
        let col = st.column.unwrap();
        assert_eq!(
            (col.name, col.label, col.unit),
            ("toy_events", "Toy events", "")
        );
        assert_eq!(
            value_at(&json, "timing.toy", st.path),
            Some(&Value::from(7))
        );
        assert_eq!(
            summary_lines(Toy::STATS, &json, "timing.toy"),
            "toy events: 7\n"
        );
    }
}
