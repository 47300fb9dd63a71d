//! Naming the field of a TOML config error: the dotted path of the offending key and, when
//! the user's text has it, its `line:col`. Configs are merged over presets as
//! `toml::Value`s (which keep no positions) before they are deserialized, so a type error
//! is traced to its field with `serde_path_to_error` and the field is then looked up in
//! the original text.

use serde::de::DeserializeOwned;

/// Merges `over` into `base`: tables key by key (recursively), any other value replaced.
/// The one merge of a user's config over its preset (chip and memory-system configs).
pub(crate) fn merge(base: &mut toml::Value, over: toml::Value) {
    match (base, over) {
        (toml::Value::Table(b), toml::Value::Table(o)) => {
            for (k, v) in o {
                match b.get_mut(&k) {
                    Some(slot) if slot.is_table() && v.is_table() => merge(slot, v),
                    _ => {
                        b.insert(k, v);
                    }
                }
            }
        }
        (b, o) => *b = o,
    }
}

/// A config error located in the user's text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FieldError {
    /// Dotted path of the field (`units.fp_add.count`), empty for the document itself.
    pub path: String,
    /// 1-based line and column of the field's value in the text, if it is there.
    pub at: Option<(usize, usize)>,
    /// What is wrong (serde's message).
    pub msg: String,
}

impl FieldError {
    /// `field `path`: msg` (the path left out when empty).
    pub fn message(&self) -> String {
        if self.path.is_empty() {
            self.msg.clone()
        } else {
            format!("field `{}`: {}", self.path, self.msg)
        }
    }
}

/// Deserializes `value` as `T`. On error, the field path is `prefix` followed by the path
/// inside `value`, and it is looked up in `text` (the document `value` came from, whose
/// keys are at `prefix`).
pub fn deserialize<T: DeserializeOwned>(
    value: toml::Value,
    text: Option<&str>,
    prefix: &[&str],
) -> Result<T, FieldError> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let mut keys: Vec<String> = prefix.iter().map(|s| s.to_string()).collect();
        for seg in e.path().iter() {
            match seg {
                serde_path_to_error::Segment::Map { key } => keys.push(key.clone()),
                serde_path_to_error::Segment::Seq { index } => keys.push(format!("[{index}]")),
                serde_path_to_error::Segment::Enum { variant } => keys.push(variant.clone()),
                serde_path_to_error::Segment::Unknown => {}
            }
        }
        let msg = e.inner().message().trim_end().to_string();
        // An unknown field's own name is in the message; its table is the path.
        let at = text.and_then(|t| locate(t, &keys));
        FieldError {
            path: keys.join(".").replace(".[", "["),
            at,
            msg,
        }
    })
}

/// The 1-based `(line, column)` of the deepest item of `keys` found in `text` (tables and
/// inline tables are followed; an array ends the walk).
pub fn locate(text: &str, keys: &[String]) -> Option<(usize, usize)> {
    let doc = toml_edit::ImDocument::parse(text).ok()?;
    let mut item = doc.as_item();
    let mut span = None;
    for k in keys {
        let Some(next) = item.as_table_like().and_then(|t| t.get(k)) else {
            break;
        };
        item = next;
        if let Some(s) = item.span() {
            span = Some(s);
        }
    }
    Some(line_col(text, span?.start))
}

/// The 1-based `(line, column)` of byte offset `at` in `text` (columns count characters).
pub fn line_col(text: &str, at: usize) -> (usize, usize) {
    let mut at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locates_keys_in_headers_dotted_keys_and_inline_tables() {
        let text = "a = 1\n[units.fp_add]\ncount = \"four\"\n[m]\nl1 = { banks = 3 }\nx.y = 2\n";
        let k = |s: &str| s.split('.').map(String::from).collect::<Vec<_>>();
        assert_eq!(locate(text, &k("a")), Some((1, 5)));
        assert_eq!(locate(text, &k("units.fp_add.count")), Some((3, 9)));
        assert_eq!(locate(text, &k("m.l1.banks")), Some((5, 16)));
        assert_eq!(locate(text, &k("m.x.y")), Some((6, 7)));
        // A key that is not there: its deepest present table.
        assert_eq!(locate(text, &k("units.fp_add.latency")), Some((2, 1)));
        assert_eq!(locate(text, &k("nothing")), None);
    }
}
