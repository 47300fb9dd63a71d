//! Formatted `trax.abort` messages: how a kernel passes a panic message with run-time
//! values (`panic!("bad id {} of {}", id, n)`, `assert_eq!`, the index of a bounds fault)
//! and how the machine renders it, exactly as Rust's `Display`/`Debug` would.
//!
//! With [`ABORT_FORMATTED`] set in `rs`, `rt` is the address of an argument *record* and
//! `rd` its length in bytes. The record is little-endian words: the template's address,
//! its length, then one 8-byte slot per argument. The template is UTF-8 text in which the
//! byte [`ESCAPE`] introduces an argument: the next byte is its [`ArgKind`] (a literal
//! `ESCAPE` byte is written twice). Arguments take the slots in order; 32-bit values sit
//! in the low word (narrower integers sign- or zero-extended), `&str` is address then
//! length. The kernel fills the record only on the failing path, so a check costs nothing
//! more when it passes.

/// Flag in `trax.abort`'s `rs`: `rt`/`rd` describe an argument record, not the message.
pub const ABORT_FORMATTED: u32 = 0x100;

/// Byte that introduces an argument in a template.
pub const ESCAPE: u8 = 0;

/// Longest template, string argument or rendered message the machine reads (bytes).
pub const MAX_TEXT: u32 = 4096;

/// Most arguments in a record.
pub const MAX_ARGS: u32 = 64;

/// How an argument is rendered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum ArgKind {
    /// `i32` (and narrower signed, sign-extended).
    I32 = b'i',
    /// `u32` (and narrower unsigned, zero-extended; `usize`).
    U32 = b'u',
    /// `i64`.
    I64 = b'I',
    /// `u64`.
    U64 = b'U',
    /// `f32`, `{}`.
    F32 = b'f',
    /// `f64`, `{}`.
    F64 = b'F',
    /// `f32`, `{:?}` (`1.0`, `1e20`).
    F32Debug = b'g',
    /// `f64`, `{:?}`.
    F64Debug = b'G',
    /// `bool`.
    Bool = b'b',
    /// `char`, `{}`.
    Char = b'c',
    /// `char`, `{:?}` (quoted, escaped).
    CharDebug = b'C',
    /// `&str`, `{}`.
    Str = b's',
    /// `&str`, `{:?}` (quoted, escaped).
    StrDebug = b'S',
}

impl ArgKind {
    /// Decodes a template kind byte.
    pub fn from_byte(b: u8) -> Option<ArgKind> {
        use ArgKind::*;
        [
            I32, U32, I64, U64, F32, F64, F32Debug, F64Debug, Bool, Char, CharDebug, Str, StrDebug,
        ]
        .into_iter()
        .find(|k| *k as u8 == b)
    }
}

/// Renders `template` with the argument slots `args`; `read(addr, len)` reads a string
/// argument's bytes from the machine's memory. Malformed input is rendered visibly
/// (`<missing argument>`, `<unreadable string at 0x...>`), never a panic.
pub fn render(
    template: &[u8],
    args: &[u64],
    mut read: impl FnMut(u32, u32) -> Option<Vec<u8>>,
) -> String {
    let mut out = Vec::new();
    let mut next = args.iter();
    let mut i = 0;
    while i < template.len() {
        let b = template[i];
        i += 1;
        if b != ESCAPE {
            out.push(b);
            continue;
        }
        let Some(&k) = template.get(i) else {
            break;
        };
        i += 1;
        if k == ESCAPE {
            out.push(ESCAPE);
            continue;
        }
        let Some(&slot) = next.next() else {
            out.extend_from_slice(b"<missing argument>");
            continue;
        };
        let lo = slot as u32;
        let hi = (slot >> 32) as u32;
        let text = match ArgKind::from_byte(k) {
            Some(ArgKind::I32) => (lo as i32).to_string(),
            Some(ArgKind::U32) => lo.to_string(),
            Some(ArgKind::I64) => (slot as i64).to_string(),
            Some(ArgKind::U64) => slot.to_string(),
            Some(ArgKind::F32) => f32::from_bits(lo).to_string(),
            Some(ArgKind::F64) => f64::from_bits(slot).to_string(),
            Some(ArgKind::F32Debug) => format!("{:?}", f32::from_bits(lo)),
            Some(ArgKind::F64Debug) => format!("{:?}", f64::from_bits(slot)),
            Some(ArgKind::Bool) => (lo != 0).to_string(),
            Some(ArgKind::Char) => char::from_u32(lo)
                .unwrap_or(char::REPLACEMENT_CHARACTER)
                .to_string(),
            Some(ArgKind::CharDebug) => {
                format!(
                    "{:?}",
                    char::from_u32(lo).unwrap_or(char::REPLACEMENT_CHARACTER)
                )
            }
            Some(kind @ (ArgKind::Str | ArgKind::StrDebug)) => match read(lo, hi.min(MAX_TEXT)) {
                Some(bytes) => {
                    let s = String::from_utf8_lossy(&bytes);
                    if kind == ArgKind::Str {
                        s.into_owned()
                    } else {
                        format!("{s:?}")
                    }
                }
                None => format!("<unreadable string at {lo:#010x}>"),
            },
            None => format!("<unknown argument kind {k:#04x}>"),
        };
        out.extend_from_slice(text.as_bytes());
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(parts: &[&[u8]]) -> Vec<u8> {
        parts.concat()
    }

    #[test]
    fn renders_like_rust_display_and_debug() {
        let tpl = t(&[
            b"bad id ",
            &[ESCAPE, b'u'],
            b" of ",
            &[ESCAPE, b'i'],
            b"; ",
            &[ESCAPE, b'g'],
            b" ",
            &[ESCAPE, b'f'],
            b" ",
            &[ESCAPE, b'S'],
            b" ",
            &[ESCAPE, b'C'],
            b" ",
            &[ESCAPE, b'I'],
            b" ",
            &[ESCAPE, ESCAPE],
        ]);
        let args = [
            7,
            (-4i32) as u32 as u64,
            1.0f32.to_bits() as u64,
            1.0f32.to_bits() as u64,
            0x1000 | (4u64 << 32),
            '\'' as u64,
            (-5i64) as u64,
        ];
        let s = render(&tpl, &args, |a, l| {
            (a == 0x1000 && l == 4).then(|| b"q\"\n\x01".to_vec())
        });
        assert_eq!(
            s,
            format!("bad id 7 of -4; 1.0 1 {:?} {:?} -5 \0", "q\"\n\x01", '\'')
        );
        assert_eq!(
            render(&[b'x', ESCAPE, b'G'], &[1e20f64.to_bits()], |_, _| None),
            format!("x{:?}", 1e20f64)
        );
    }

    #[test]
    fn malformed_records_render_visibly() {
        assert_eq!(
            render(&[ESCAPE, b'i'], &[], |_, _| None),
            "<missing argument>"
        );
        assert_eq!(
            render(&[ESCAPE, b's'], &[0x40], |_, _| None),
            "<unreadable string at 0x00000040>"
        );
        assert_eq!(
            render(&[ESCAPE, b'z'], &[0], |_, _| None),
            "<unknown argument kind 0x7a>"
        );
        assert_eq!(render(b"ab\0", &[], |_, _| None), "ab");
    }
}
