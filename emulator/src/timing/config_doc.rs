//! The resolved chip config as TOML with every field's doc comment as a TOML comment
//! (`trax config show`). The comments are read from the config types' own `///` doc
//! comments (the source files are embedded at compile time), so the documentation of a
//! field lives in one place, on the field.

use std::collections::HashMap;
use std::fmt::Write as _;

use super::ChipConfig;

/// The source files that declare the chip config's types.
const SOURCES: &[&str] = &[
    include_str!("config.rs"),
    include_str!("../memsys/config.rs"),
    include_str!("../memsys/dram_config.rs"),
];

/// One documented field: its doc comment, the name of its (innermost) type, and whether
/// it is a map (a table of entries of that type).
struct FieldDoc {
    doc: String,
    ty: String,
    map: bool,
}

/// Struct name -> TOML key -> field.
type Docs = HashMap<String, HashMap<String, FieldDoc>>;

/// Reads the fields of every `pub struct` with their `///` comments and `serde(rename)`s.
fn parse_docs() -> Docs {
    let mut docs: Docs = HashMap::new();
    for src in SOURCES {
        let mut current: Option<String> = None;
        let mut pending: Vec<String> = Vec::new();
        let mut rename: Option<String> = None;
        for line in src.lines() {
            let t = line.trim();
            if let Some(rest) = t.strip_prefix("pub struct ") {
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                current = (rest.trim_end().ends_with('{')).then_some(name);
                pending.clear();
                continue;
            }
            if line.starts_with('}') {
                current = None;
            }
            let Some(st) = &current else { continue };
            if let Some(d) = t.strip_prefix("///") {
                pending.push(d.strip_prefix(' ').unwrap_or(d).to_string());
            } else if let Some(r) = t
                .strip_prefix("#[serde(rename = \"")
                .and_then(|r| r.split('"').next())
            {
                rename = Some(r.to_string());
            } else if t.starts_with("#[") {
            } else if let Some((name, ty)) = t
                .strip_prefix("pub ")
                .and_then(|f| f.split_once(':'))
                .filter(|(n, _)| n.chars().all(|c| c.is_alphanumeric() || c == '_'))
            {
                let ty = ty.trim().trim_end_matches(',');
                // The innermost named type: `BTreeMap<String, UnitConfig>` -> `UnitConfig`.
                let inner = ty
                    .trim_end_matches('>')
                    .rsplit(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .next()
                    .unwrap_or(ty)
                    .to_string();
                let key = rename.take().unwrap_or_else(|| name.to_string());
                docs.entry(st.clone()).or_default().insert(
                    key,
                    FieldDoc {
                        doc: pending.join(" "),
                        ty: inner,
                        map: ty.contains("Map<"),
                    },
                );
                pending.clear();
            } else {
                pending.clear();
                rename = None;
            }
        }
    }
    docs
}

/// `text` as `# ` comment lines of at most about 92 columns.
fn comment(out: &mut String, text: &str) {
    let mut line = String::new();
    for w in text.split_whitespace() {
        if !line.is_empty() && line.len() + w.len() > 90 {
            let _ = writeln!(out, "# {line}");
            line.clear();
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(w);
    }
    if !line.is_empty() {
        let _ = writeln!(out, "# {line}");
    }
}

/// A TOML key, quoted unless bare.
fn key(k: &str) -> String {
    if !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        k.to_string()
    } else {
        toml::Value::String(k.to_string()).to_string()
    }
}

/// Writes `table` (whose fields are those of struct `ty`, or a map of `ty` when `map`)
/// under header `path`.
fn render(out: &mut String, docs: &Docs, path: &str, ty: &str, table: &toml::Table, map: bool) {
    let fields = docs.get(ty);
    let sub = |k: &str| -> (String, bool) {
        if map {
            return (ty.to_string(), false);
        }
        // A map's values are tables of one struct each (`units.NAME`).
        match fields.and_then(|f| f.get(k)) {
            Some(f) => (f.ty.clone(), f.map),
            None => (String::new(), false),
        }
    };
    let doc_of = |k: &str| fields.and_then(|f| f.get(k)).map(|f| f.doc.as_str());
    for (k, v) in table {
        if v.is_table() {
            continue;
        }
        if !map {
            if let Some(d) = doc_of(k).filter(|d| !d.is_empty()) {
                comment(out, d);
            }
        }
        let _ = writeln!(out, "{} = {v}", key(k));
    }
    let mut first_entry = true;
    for (k, v) in table {
        let Some(t) = v.as_table() else { continue };
        let p = if path.is_empty() {
            key(k)
        } else {
            format!("{path}.{}", key(k))
        };
        let (mut sub_ty, sub_map) = sub(k);
        if map && !std::mem::take(&mut first_entry) {
            // A map's entries share their fields' comments: given once, at the first.
            sub_ty.clear();
        }
        let _ = writeln!(out);
        if let Some(d) = doc_of(k).filter(|d| !d.is_empty() && !map) {
            comment(out, d);
        }
        // An execution unit's table: what the unit is, from its declaration.
        if let Some(u) = (path == "units").then(|| super::units::named(k)).flatten() {
            comment(out, u.doc);
        }
        let _ = writeln!(out, "[{p}]");
        render(out, docs, &p, &sub_ty, t, sub_map);
    }
}

impl ChipConfig {
    /// The complete configuration as TOML, every field with its doc comment (its meaning,
    /// unit and default) as a `#` comment above it; `header` lines go first as comments.
    /// The text loads back as the same configuration
    /// ([`ChipConfig::from_toml_str`]).
    pub fn to_documented_toml(&self, header: &[String]) -> String {
        let docs = parse_docs();
        let mut out = String::new();
        for h in header {
            let _ = writeln!(out, "# {h}");
        }
        if !header.is_empty() {
            let _ = writeln!(out);
        }
        let value = toml::Value::try_from(self).unwrap_or(toml::Value::Table(toml::Table::new()));
        if let Some(t) = value.as_table() {
            render(&mut out, &docs, "", "ChipConfig", t, false);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::timing::CHIP_PRESETS;

    /// Every preset's documented TOML loads back as the preset, and every field of the
    /// config types has its comment.
    #[test]
    fn documented_toml_round_trips_with_a_comment_per_field() {
        for name in CHIP_PRESETS {
            let chip = ChipConfig::preset(name).unwrap();
            let text = chip.to_documented_toml(&[format!("preset {name}")]);
            let back = ChipConfig::from_toml_str(&text, name).unwrap();
            assert_eq!(back, chip, "{name}");
            // Every key line of a struct field follows a comment (map entries such as
            // `units.fp_add` are documented at their map).
            let lines: Vec<&str> = text.lines().collect();
            let mut in_map_entry = false;
            for (i, l) in lines.iter().enumerate() {
                if l.starts_with('[') {
                    in_map_entry = l.starts_with("[units.");
                    continue;
                }
                if l.is_empty() || l.starts_with('#') || in_map_entry {
                    continue;
                }
                assert!(
                    lines[i - 1].starts_with('#'),
                    "{name}: `{l}` has no comment:\n{text}"
                );
            }
        }
        let docs = parse_docs();
        let l2 = &docs["MemSysConfig"]["l2"];
        assert_eq!(l2.ty, "L2Config");
        assert!(docs["DramTimingSpec"].contains_key("tRCD"), "renamed field");
        assert!(docs["PipelinesConfig"].contains_key("box"), "renamed field");
    }
}
