//! Formatted messages: how a kernel passes text with run-time values — a formatted print
//! (`println!("{:>8.3} {:?}", x, hit)`, one `trax.printfmt`), a panic message
//! (`panic!("bad id {} of {}", id, n)`, `assert_eq!`, a bounds fault; `trax.abort` with
//! [`ABORT_FORMATTED`]) — and how the machine renders it, exactly as Rust's
//! `Display`/`Debug`/`LowerHex`/... with width, fill, alignment, sign, `#`, `0` and
//! precision would: the core text of every value comes from Rust's own formatting, and
//! padding follows `core::fmt::Formatter`'s rules.
//!
//! A *record* is little-endian words: the template's address, its length, then one
//! 8-byte slot per argument. The template is UTF-8 text in which the byte [`ESCAPE`]
//! introduces an argument (a literal `ESCAPE` byte is written twice). An argument is:
//! a value kind byte ([`ValueKind`]; an integer kind is followed by its size in bytes), a
//! flags byte (bit 0 `+`, bit 1 `#`, bit 2 `0`, bits 3-4 alignment none/`<`/`^`/`>`,
//! bit 5 width given, bit 6 precision given), the trait byte ([`Trait`]), the fill
//! character (UTF-8) when aligned, then the width and the precision as `u32` each when
//! given, [`FROM_SLOT`] meaning "the next slot's low word". Slots are taken in template
//! order: width, precision, then the value. 32-bit values sit in the low word (narrower
//! integers sign- or zero-extended), `&str` is address then length, and a value shown
//! with `{:?}` through a *type descriptor* ([`ValueKind::Described`]) is its address then
//! the descriptor's address. The kernel fills the record only on the failing path of a
//! check, so a check costs nothing more when it passes.
//!
//! A type descriptor (compiler-generated, read-only data) starts with its length (`u32`)
//! and then one node ([`desc`]); the renderer reads the value's memory through it and
//! builds the text with `Formatter::debug_struct`/`debug_tuple`/`debug_list`, so `{:#?}`
//! is Rust's pretty form.

use std::fmt::{self, Write as _};

/// Flag in `trax.abort`'s `rs`: `rt`/`rd` describe an argument record, not the message.
pub const ABORT_FORMATTED: u32 = 0x100;

/// Byte that introduces an argument in a template.
pub const ESCAPE: u8 = 0;

/// Longest template, string argument or rendered message the machine reads (bytes).
pub const MAX_TEXT: u32 = 4096;

/// Most arguments in a record.
pub const MAX_ARGS: u32 = 64;

/// Width or precision taken from the next slot.
pub const FROM_SLOT: u32 = u32::MAX;

/// Longest type descriptor (bytes).
pub const MAX_DESC: u32 = 1 << 16;

/// Most values (leaves and nodes) one `{:?}` argument renders.
const MAX_NODES: usize = 1 << 16;

/// The kind of an argument's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum ValueKind {
    /// Signed integer (followed by its size: 1, 2, 4 or 8).
    Int = b'i',
    /// Unsigned integer (followed by its size).
    Uint = b'u',
    /// `f32` (bits in the low word).
    F32 = b'f',
    /// `f64`.
    F64 = b'F',
    /// `bool`.
    Bool = b'b',
    /// `char`.
    Char = b'c',
    /// `&str`: address, length.
    Str = b's',
    /// `()`.
    Unit = b'(',
    /// A value at an address, shown through a type descriptor: address, descriptor.
    Described = b'd',
}

impl ValueKind {
    fn from_byte(b: u8) -> Option<ValueKind> {
        use ValueKind::*;
        [Int, Uint, F32, F64, Bool, Char, Str, Unit, Described]
            .into_iter()
            .find(|k| *k as u8 == b)
    }
}

/// The formatting trait of an argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Trait {
    Display = b'D',
    Debug = b'?',
    /// `{:x?}`.
    DebugLowerHex = b'h',
    /// `{:X?}`.
    DebugUpperHex = b'H',
    LowerHex = b'x',
    UpperHex = b'X',
    Octal = b'o',
    Binary = b'b',
    LowerExp = b'e',
    UpperExp = b'E',
}

impl Trait {
    fn from_byte(b: u8) -> Option<Trait> {
        use Trait::*;
        [
            Display,
            Debug,
            DebugLowerHex,
            DebugUpperHex,
            LowerHex,
            UpperHex,
            Octal,
            Binary,
            LowerExp,
            UpperExp,
        ]
        .into_iter()
        .find(|k| *k as u8 == b)
    }

    fn is_debug(self) -> bool {
        matches!(
            self,
            Trait::Debug | Trait::DebugLowerHex | Trait::DebugUpperHex
        )
    }
}

/// Alignment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    None = 0,
    Left = 1,
    Center = 2,
    Right = 3,
}

/// A width or precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Count {
    None,
    Is(u32),
    /// From the next slot.
    Slot,
}

/// An argument's format spec.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Spec {
    pub fill: char,
    pub align: Align,
    pub plus: bool,
    pub alternate: bool,
    pub zero: bool,
    pub width: Count,
    pub precision: Count,
    pub tr: Trait,
}

impl Spec {
    /// `{}`.
    pub fn display() -> Spec {
        Spec {
            fill: ' ',
            align: Align::None,
            plus: false,
            alternate: false,
            zero: false,
            width: Count::None,
            precision: Count::None,
            tr: Trait::Display,
        }
    }

    /// `{:?}`.
    pub fn debug() -> Spec {
        Spec {
            tr: Trait::Debug,
            ..Spec::display()
        }
    }

    /// Appends the template encoding of an argument of kind `kind` (with `size` for
    /// integers) and this spec.
    pub fn encode(&self, kind: ValueKind, size: u8, out: &mut Vec<u8>) {
        out.push(ESCAPE);
        out.push(kind as u8);
        if matches!(kind, ValueKind::Int | ValueKind::Uint) {
            out.push(size);
        }
        let mut f = self.plus as u8 | (self.alternate as u8) << 1 | (self.zero as u8) << 2;
        f |= (self.align as u8) << 3;
        f |= ((self.width != Count::None) as u8) << 5;
        f |= ((self.precision != Count::None) as u8) << 6;
        out.push(f);
        out.push(self.tr as u8);
        if self.align != Align::None {
            let mut b = [0; 4];
            out.extend_from_slice(self.fill.encode_utf8(&mut b).as_bytes());
        }
        for c in [self.width, self.precision] {
            match c {
                Count::None => {}
                Count::Is(n) => out.extend_from_slice(&n.to_le_bytes()),
                Count::Slot => out.extend_from_slice(&FROM_SLOT.to_le_bytes()),
            }
        }
    }
}

/// Appends literal text to a template (escaping `ESCAPE` bytes).
pub fn push_text(text: &str, out: &mut Vec<u8>) {
    for b in text.bytes() {
        if b == ESCAPE {
            out.push(ESCAPE);
        }
        out.push(b);
    }
}

/// Type descriptor nodes (each a tag byte and its payload; strings are a `u16` length
/// and UTF-8; offsets and sizes `u32`).
pub mod desc {
    /// Signed integer: size `u8`.
    pub const INT: u8 = b'i';
    /// Unsigned integer: size `u8`.
    pub const UINT: u8 = b'u';
    /// `f32`.
    pub const F32: u8 = b'f';
    /// `f64`.
    pub const F64: u8 = b'F';
    /// `bool`.
    pub const BOOL: u8 = b'b';
    /// `char`.
    pub const CHAR: u8 = b'c';
    /// `&str` (address, length).
    pub const STR: u8 = b's';
    /// `()`.
    pub const UNIT: u8 = b'(';
    /// Raw pointer (shown as its address).
    pub const PTR: u8 = b'p';
    /// Reference: the pointee's node follows (shown as the pointee).
    pub const REF: u8 = b'r';
    /// Struct with named fields: name, count `u16`, then per field its name, offset and
    /// node.
    pub const STRUCT: u8 = b'S';
    /// Tuple struct: name, count, then per field its offset and node.
    pub const TUPLE_STRUCT: u8 = b'T';
    /// Unit struct: name.
    pub const UNIT_STRUCT: u8 = b'U';
    /// Tuple: count, then per element its offset and node.
    pub const TUPLE: u8 = b't';
    /// Array: length `u32`, stride `u32`, element node.
    pub const ARRAY: u8 = b'a';
    /// Slice reference (address, length): stride, element node.
    pub const SLICE: u8 = b'l';
    /// Enum: tag offset `u32`, tag size `u8`, signed `u8`, variant count `u16`, then per
    /// variant its discriminant (`i64`) and a `STRUCT`/`TUPLE_STRUCT`/`UNIT_STRUCT` node
    /// whose offsets are from the enum's start.
    pub const ENUM: u8 = b'E';
}

/// Renders a template with the argument slots `args`; `read(addr, len)` reads the
/// machine's memory (strings, described values, descriptors). Malformed input is
/// rendered visibly (`<missing argument>`, `<unreadable string at 0x...>`), never a
/// panic.
pub fn render(
    template: &[u8],
    args: &[u64],
    mut read: impl FnMut(u32, u32) -> Option<Vec<u8>>,
) -> String {
    let mut out = String::new();
    let mut next = args.iter().copied();
    let mut i = 0;
    let mut text = Vec::new();
    while i < template.len() {
        let b = template[i];
        i += 1;
        if b != ESCAPE {
            text.push(b);
            continue;
        }
        let Some(&k) = template.get(i) else {
            break;
        };
        i += 1;
        if k == ESCAPE {
            text.push(ESCAPE);
            continue;
        }
        out.push_str(&String::from_utf8_lossy(&std::mem::take(&mut text)));
        match parse_arg(template, &mut i, k) {
            Some((kind, size, spec)) => {
                let mut take = || next.next();
                out.push_str(&render_arg(kind, size, spec, &mut take, &mut read));
            }
            None => {
                out.push_str(&format!("<malformed argument {k:#04x}>"));
                break;
            }
        }
    }
    out.push_str(&String::from_utf8_lossy(&text));
    out
}

fn parse_arg(t: &[u8], i: &mut usize, k: u8) -> Option<(ValueKind, u8, Spec)> {
    let kind = ValueKind::from_byte(k)?;
    let mut byte = || {
        let b = *t.get(*i)?;
        *i += 1;
        Some(b)
    };
    let size = if matches!(kind, ValueKind::Int | ValueKind::Uint) {
        byte()?
    } else {
        0
    };
    let f = byte()?;
    let tr = Trait::from_byte(byte()?)?;
    let align = match (f >> 3) & 3 {
        0 => Align::None,
        1 => Align::Left,
        2 => Align::Center,
        _ => Align::Right,
    };
    let mut fill = ' ';
    if align != Align::None {
        let rest = t.get(*i..)?;
        let n = match rest.first()? {
            b if *b < 0x80 => 1,
            b if *b >= 0xF0 => 4,
            b if *b >= 0xE0 => 3,
            _ => 2,
        };
        fill = std::str::from_utf8(rest.get(..n)?).ok()?.chars().next()?;
        *i += n;
    }
    let mut count = |given: bool| -> Option<Count> {
        if !given {
            return Some(Count::None);
        }
        let w = t.get(*i..*i + 4)?;
        *i += 4;
        let v = u32::from_le_bytes([w[0], w[1], w[2], w[3]]);
        Some(if v == FROM_SLOT {
            Count::Slot
        } else {
            Count::Is(v)
        })
    };
    let width = count(f & 0x20 != 0)?;
    let precision = count(f & 0x40 != 0)?;
    Some((
        kind,
        size,
        Spec {
            fill,
            align,
            plus: f & 1 != 0,
            alternate: f & 2 != 0,
            zero: f & 4 != 0,
            width,
            precision,
            tr,
        },
    ))
}

/// A resolved spec: counts read from slots.
#[derive(Clone, Copy)]
struct Resolved {
    spec: Spec,
    width: Option<usize>,
    precision: Option<usize>,
}

/// A leaf value.
#[derive(Clone, Debug)]
enum Leaf {
    I64(i64, u8),
    U64(u64, u8),
    F32(f32),
    F64(f64),
    Bool(bool),
    Char(char),
    Str(String),
    Unit,
    Ptr(u32),
}

fn render_arg(
    kind: ValueKind,
    size: u8,
    spec: Spec,
    take: &mut dyn FnMut() -> Option<u64>,
    read: &mut dyn FnMut(u32, u32) -> Option<Vec<u8>>,
) -> String {
    let mut count = |c: Count| -> Result<Option<usize>, ()> {
        match c {
            Count::None => Ok(None),
            Count::Is(n) => Ok(Some(n as usize)),
            Count::Slot => take().map(|v| Some(v as u32 as usize)).ok_or(()),
        }
    };
    let (Ok(width), Ok(precision)) = (count(spec.width), count(spec.precision)) else {
        return "<missing argument>".into();
    };
    let r = Resolved {
        spec,
        width,
        precision,
    };
    let Some(slot) = take() else {
        return "<missing argument>".into();
    };
    let lo = slot as u32;
    let hi = (slot >> 32) as u32;
    let leaf = match kind {
        ValueKind::Int => Leaf::I64(sign_extend(slot, size), size),
        ValueKind::Uint => Leaf::U64(zero_extend(slot, size), size),
        ValueKind::F32 => Leaf::F32(f32::from_bits(lo)),
        ValueKind::F64 => Leaf::F64(f64::from_bits(slot)),
        ValueKind::Bool => Leaf::Bool(lo != 0),
        ValueKind::Char => Leaf::Char(char::from_u32(lo).unwrap_or(char::REPLACEMENT_CHARACTER)),
        ValueKind::Unit => Leaf::Unit,
        ValueKind::Str => match read(lo, hi.min(MAX_TEXT)) {
            Some(bytes) => Leaf::Str(String::from_utf8_lossy(&bytes).into_owned()),
            None => return format!("<unreadable string at {lo:#010x}>"),
        },
        ValueKind::Described => {
            let Some(d) = read_desc(hi, read) else {
                return format!("<unreadable type descriptor at {hi:#010x}>");
            };
            let mut budget = MAX_NODES;
            let node = build(&d, &mut 0, lo, read, &mut budget, 0);
            let tree = Tree { node: &node, r };
            return if spec.alternate {
                format!("{tree:#?}")
            } else {
                format!("{tree:?}")
            };
        }
    };
    fmt_leaf(&leaf, &r)
}

fn sign_extend(v: u64, size: u8) -> i64 {
    match size {
        1 => v as i8 as i64,
        2 => v as i16 as i64,
        4 => v as i32 as i64,
        _ => v as i64,
    }
}

fn zero_extend(v: u64, size: u8) -> u64 {
    match size {
        1 => v as u8 as u64,
        2 => v as u16 as u64,
        4 => v as u32 as u64,
        _ => v,
    }
}

/// The value's text without width: Rust's formatting with the spec's sign, `#` and
/// precision.
macro_rules! core_fmt {
    ($v:expr, $r:expr, $ty:literal) => {{
        let (plus, alt) = ($r.spec.plus, $r.spec.alternate);
        match ($r.precision, plus, alt) {
            (None, false, false) => format!(concat!("{:", $ty, "}"), $v),
            (None, true, false) => format!(concat!("{:+", $ty, "}"), $v),
            (None, false, true) => format!(concat!("{:#", $ty, "}"), $v),
            (None, true, true) => format!(concat!("{:+#", $ty, "}"), $v),
            (Some(p), false, false) => format!(concat!("{:.p$", $ty, "}"), $v, p = p),
            (Some(p), true, false) => format!(concat!("{:+.p$", $ty, "}"), $v, p = p),
            (Some(p), false, true) => format!(concat!("{:#.p$", $ty, "}"), $v, p = p),
            (Some(p), true, true) => format!(concat!("{:+#.p$", $ty, "}"), $v, p = p),
        }
    }};
}

/// Formats a value of an integer type with its width in bytes as Rust would for that
/// type (hex, octal and binary show the two's complement of the type's width).
fn int_core(v: i128, size: u8, signed: bool, r: &Resolved) -> String {
    let bits = size as u32 * 8;
    let mask: u128 = if bits >= 128 {
        u128::MAX
    } else {
        (1u128 << bits) - 1
    };
    let u = (v as u128) & mask;
    match r.spec.tr {
        Trait::LowerHex | Trait::DebugLowerHex => core_fmt!(u, r, "x"),
        Trait::UpperHex | Trait::DebugUpperHex => core_fmt!(u, r, "X"),
        Trait::Octal => core_fmt!(u, r, "o"),
        Trait::Binary => core_fmt!(u, r, "b"),
        Trait::LowerExp if signed => core_fmt!(v as i64, r, "e"),
        Trait::LowerExp => core_fmt!(u as u64, r, "e"),
        Trait::UpperExp if signed => core_fmt!(v as i64, r, "E"),
        Trait::UpperExp => core_fmt!(u as u64, r, "E"),
        _ if signed => core_fmt!(v as i64, r, ""),
        _ => core_fmt!(u as u64, r, ""),
    }
}

/// A leaf formatted with its spec: Rust's text, then `Formatter`'s padding.
fn fmt_leaf(l: &Leaf, r: &Resolved) -> String {
    let t = r.spec.tr;
    let (core, numeric, pads) = match l {
        Leaf::I64(v, s) => (int_core(*v as i128, *s, true, r), true, true),
        Leaf::U64(v, s) => (int_core(*v as i128, *s, false, r), true, true),
        Leaf::F32(v) => (float_core(*v as f64, Some(*v), r), true, true),
        Leaf::F64(v) => (float_core(*v, None, r), true, true),
        Leaf::Bool(b) => (core_fmt!(b, r, ""), false, true),
        // `Debug` of `char` and `str` writes the quoted text without padding.
        Leaf::Char(c) if t.is_debug() => (format!("{c:?}"), false, false),
        Leaf::Char(c) => (core_fmt!(c, r, ""), false, true),
        Leaf::Str(s) if t.is_debug() => (format!("{s:?}"), false, false),
        Leaf::Str(s) => (core_fmt!(s, r, ""), false, true),
        Leaf::Unit => (core_fmt!("()", r, ""), false, true),
        Leaf::Ptr(p) => (format!("{:#x}", p), true, true),
    };
    let Some(width) = r.width else { return core };
    let n = core.chars().count();
    if !pads || n >= width {
        return core;
    }
    let pad = width - n;
    if numeric && r.spec.zero {
        // Sign-aware zero padding: sign and `0x`-style prefix first, then zeros.
        let mut split = 0;
        let bytes = core.as_bytes();
        if matches!(bytes.first(), Some(b'+' | b'-')) {
            split = 1;
        }
        let prefixed = r.spec.alternate
            && matches!(
                t,
                Trait::LowerHex
                    | Trait::UpperHex
                    | Trait::Octal
                    | Trait::Binary
                    | Trait::DebugLowerHex
                    | Trait::DebugUpperHex
            );
        if prefixed
            && core[split..].len() >= 2
            && matches!(&core[split..split + 2], "0x" | "0o" | "0b")
        {
            split += 2;
        }
        let mut s = String::with_capacity(width);
        s.push_str(&core[..split]);
        s.extend(std::iter::repeat_n('0', pad));
        s.push_str(&core[split..]);
        return s;
    }
    let align = match r.spec.align {
        Align::None if numeric => Align::Right,
        Align::None => Align::Left,
        a => a,
    };
    let (pre, post) = match align {
        Align::Left => (0, pad),
        Align::Right => (pad, 0),
        _ => (pad / 2, pad.div_ceil(2)),
    };
    let fill = r.spec.fill;
    let mut s = String::with_capacity(core.len() + pad * fill.len_utf8());
    s.extend(std::iter::repeat_n(fill, pre));
    s.push_str(&core);
    s.extend(std::iter::repeat_n(fill, post));
    s
}

fn float_core(v: f64, f32v: Option<f32>, r: &Resolved) -> String {
    macro_rules! both {
        ($ty:literal) => {
            match f32v {
                Some(x) => core_fmt!(x, r, $ty),
                None => core_fmt!(v, r, $ty),
            }
        };
    }
    match r.spec.tr {
        Trait::LowerExp => both!("e"),
        Trait::UpperExp => both!("E"),
        Trait::Debug | Trait::DebugLowerHex | Trait::DebugUpperHex => both!("?"),
        _ => both!(""),
    }
}

/// A value read through a descriptor.
enum Node {
    Leaf(Leaf),
    Struct(String, Vec<(String, Node)>),
    Tuple(String, Vec<Node>),
    UnitStruct(String),
    List(Vec<Node>),
    Error(String),
}

struct Tree<'a> {
    node: &'a Node,
    r: Resolved,
}

impl fmt::Debug for Tree<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sub = |n| Tree { node: n, r: self.r };
        match self.node {
            Node::Leaf(l) => f.write_str(&fmt_leaf(l, &self.r)),
            Node::Struct(name, fields) if fields.is_empty() => f.write_str(name),
            Node::Struct(name, fields) => {
                let mut d = f.debug_struct(name);
                for (n, v) in fields {
                    d.field(n, &sub(v));
                }
                d.finish()
            }
            Node::Tuple(name, elems) if elems.is_empty() && !name.is_empty() => f.write_str(name),
            Node::Tuple(name, elems) => {
                let mut d = f.debug_tuple(name);
                for v in elems {
                    d.field(&sub(v));
                }
                d.finish()
            }
            Node::UnitStruct(name) => f.write_str(name),
            Node::List(elems) => f.debug_list().entries(elems.iter().map(sub)).finish(),
            Node::Error(e) => f.write_str(e),
        }
    }
}

fn read_desc(addr: u32, read: &mut dyn FnMut(u32, u32) -> Option<Vec<u8>>) -> Option<Vec<u8>> {
    let h = read(addr, 4)?;
    let len = u32::from_le_bytes([h[0], h[1], h[2], h[3]]);
    if len > MAX_DESC {
        return None;
    }
    read(addr.wrapping_add(4), len)
}

/// Reads a value at `addr` through the descriptor node at `d[*i..]`; `*i` moves past the
/// node whatever the memory reads give.
fn build(
    d: &[u8],
    i: &mut usize,
    addr: u32,
    read: &mut dyn FnMut(u32, u32) -> Option<Vec<u8>>,
    budget: &mut usize,
    depth: u32,
) -> Node {
    let mut end = *i;
    if skip(d, &mut end, depth).is_none() {
        *i = d.len();
        return Node::Error("<malformed type descriptor>".into());
    }
    let mut j = *i;
    *i = end;
    if *budget == 0 || depth > 64 {
        return Node::Error("<...>".into());
    }
    *budget -= 1;
    match build_inner(d, &mut j, addr, read, budget, depth) {
        Some(n) => n,
        None => Node::Error(format!("<unreadable value at {addr:#010x}>")),
    }
}

fn u8_at(d: &[u8], i: &mut usize) -> Option<u8> {
    let b = *d.get(*i)?;
    *i += 1;
    Some(b)
}

fn u16_at(d: &[u8], i: &mut usize) -> Option<u16> {
    let b = d.get(*i..*i + 2)?;
    *i += 2;
    Some(u16::from_le_bytes([b[0], b[1]]))
}

fn u32_at(d: &[u8], i: &mut usize) -> Option<u32> {
    let b = d.get(*i..*i + 4)?;
    *i += 4;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

fn str_at(d: &[u8], i: &mut usize) -> Option<String> {
    let n = u16_at(d, i)? as usize;
    let b = d.get(*i..*i + n)?;
    *i += n;
    Some(String::from_utf8_lossy(b).into_owned())
}

/// Skips the node at `d[*i..]`.
fn skip(d: &[u8], i: &mut usize, depth: u32) -> Option<()> {
    if depth > 64 {
        return None;
    }
    match u8_at(d, i)? {
        desc::INT | desc::UINT => {
            u8_at(d, i)?;
        }
        desc::F32 | desc::F64 | desc::BOOL | desc::CHAR | desc::STR | desc::UNIT | desc::PTR => {}
        desc::REF => skip(d, i, depth + 1)?,
        desc::STRUCT => {
            str_at(d, i)?;
            for _ in 0..u16_at(d, i)? {
                str_at(d, i)?;
                u32_at(d, i)?;
                skip(d, i, depth + 1)?;
            }
        }
        desc::TUPLE_STRUCT => {
            str_at(d, i)?;
            for _ in 0..u16_at(d, i)? {
                u32_at(d, i)?;
                skip(d, i, depth + 1)?;
            }
        }
        desc::UNIT_STRUCT => {
            str_at(d, i)?;
        }
        desc::TUPLE => {
            for _ in 0..u16_at(d, i)? {
                u32_at(d, i)?;
                skip(d, i, depth + 1)?;
            }
        }
        desc::ARRAY => {
            u32_at(d, i)?;
            u32_at(d, i)?;
            skip(d, i, depth + 1)?;
        }
        desc::SLICE => {
            u32_at(d, i)?;
            skip(d, i, depth + 1)?;
        }
        desc::ENUM => {
            u32_at(d, i)?;
            u8_at(d, i)?;
            u8_at(d, i)?;
            for _ in 0..u16_at(d, i)? {
                d.get(*i..*i + 8)?;
                *i += 8;
                skip(d, i, depth + 1)?;
            }
        }
        _ => return None,
    }
    Some(())
}

fn word(read: &mut dyn FnMut(u32, u32) -> Option<Vec<u8>>, addr: u32, size: u32) -> Option<u64> {
    let b = read(addr, size)?;
    let mut v = [0u8; 8];
    v[..b.len().min(8)].copy_from_slice(&b[..b.len().min(8)]);
    Some(u64::from_le_bytes(v))
}

fn build_inner(
    d: &[u8],
    i: &mut usize,
    addr: u32,
    read: &mut dyn FnMut(u32, u32) -> Option<Vec<u8>>,
    budget: &mut usize,
    depth: u32,
) -> Option<Node> {
    let tag = u8_at(d, i)?;
    Some(match tag {
        desc::INT | desc::UINT => {
            let size = u8_at(d, i)?;
            let v = word(read, addr, size as u32)?;
            Node::Leaf(if tag == desc::INT {
                Leaf::I64(sign_extend(v, size), size)
            } else {
                Leaf::U64(zero_extend(v, size), size)
            })
        }
        desc::F32 => Node::Leaf(Leaf::F32(f32::from_bits(word(read, addr, 4)? as u32))),
        desc::F64 => Node::Leaf(Leaf::F64(f64::from_bits(word(read, addr, 8)?))),
        desc::BOOL => Node::Leaf(Leaf::Bool(word(read, addr, 1)? != 0)),
        desc::CHAR => Node::Leaf(Leaf::Char(
            char::from_u32(word(read, addr, 4)? as u32).unwrap_or(char::REPLACEMENT_CHARACTER),
        )),
        desc::UNIT => Node::Leaf(Leaf::Unit),
        desc::PTR => Node::Leaf(Leaf::Ptr(word(read, addr, 4)? as u32)),
        desc::STR => {
            let a = word(read, addr, 4)? as u32;
            let n = word(read, addr.wrapping_add(4), 4)? as u32;
            let b = read(a, n.min(MAX_TEXT))?;
            Node::Leaf(Leaf::Str(String::from_utf8_lossy(&b).into_owned()))
        }
        desc::REF => {
            let p = word(read, addr, 4)? as u32;
            build(d, i, p, read, budget, depth + 1)
        }
        desc::STRUCT => {
            let name = str_at(d, i)?;
            let n = u16_at(d, i)?;
            let mut fields = Vec::new();
            for _ in 0..n {
                let fname = str_at(d, i)?;
                let off = u32_at(d, i)?;
                fields.push((
                    fname,
                    build(d, i, addr.wrapping_add(off), read, budget, depth + 1),
                ));
            }
            Node::Struct(name, fields)
        }
        desc::TUPLE_STRUCT | desc::TUPLE => {
            let name = if tag == desc::TUPLE_STRUCT {
                str_at(d, i)?
            } else {
                String::new()
            };
            let n = u16_at(d, i)?;
            let mut elems = Vec::new();
            for _ in 0..n {
                let off = u32_at(d, i)?;
                elems.push(build(d, i, addr.wrapping_add(off), read, budget, depth + 1));
            }
            Node::Tuple(name, elems)
        }
        desc::UNIT_STRUCT => Node::UnitStruct(str_at(d, i)?),
        desc::ARRAY | desc::SLICE => {
            let (base, len) = if tag == desc::ARRAY {
                (addr, u32_at(d, i)?)
            } else {
                (
                    word(read, addr, 4)? as u32,
                    word(read, addr.wrapping_add(4), 4)? as u32,
                )
            };
            let stride = u32_at(d, i)?;
            let start = *i;
            let mut elems = Vec::new();
            for k in 0..len {
                if *budget == 0 {
                    elems.push(Node::Error("<...>".into()));
                    break;
                }
                let mut j = start;
                elems.push(build(
                    d,
                    &mut j,
                    base.wrapping_add(k.wrapping_mul(stride)),
                    read,
                    budget,
                    depth + 1,
                ));
            }
            skip(d, i, depth + 1)?;
            Node::List(elems)
        }
        desc::ENUM => {
            let toff = u32_at(d, i)?;
            let tsize = u8_at(d, i)?;
            let signed = u8_at(d, i)? != 0;
            let n = u16_at(d, i)?;
            let raw = word(read, addr.wrapping_add(toff), tsize as u32)?;
            let tag = if signed {
                sign_extend(raw, tsize)
            } else {
                zero_extend(raw, tsize) as i64
            };
            let mut found = None;
            for _ in 0..n {
                let b = d.get(*i..*i + 8)?;
                *i += 8;
                let discr = i64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]);
                if discr == tag && found.is_none() {
                    found = Some(build(d, i, addr, read, budget, depth + 1));
                } else {
                    skip(d, i, depth + 1)?;
                }
            }
            found.unwrap_or_else(|| Node::Error(format!("<invalid discriminant {tag}>")))
        }
        _ => return None,
    })
}

/// Writes `s` into `out` (for callers rendering into a buffer).
pub fn write_into(out: &mut String, s: &str) {
    let _ = out.write_str(s);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arg(kind: ValueKind, size: u8, spec: Spec) -> Vec<u8> {
        let mut v = Vec::new();
        spec.encode(kind, size, &mut v);
        v
    }

    fn spec(s: &str) -> Spec {
        // A tiny parser for tests: [fill]align? + # 0 width .prec type
        let mut sp = Spec::display();
        let c: Vec<char> = s.chars().collect();
        let mut i = 0;
        let al = |c: char| match c {
            '<' => Some(Align::Left),
            '^' => Some(Align::Center),
            '>' => Some(Align::Right),
            _ => None,
        };
        if c.len() >= 2 && al(c[1]).is_some() {
            sp.fill = c[0];
            sp.align = al(c[1]).unwrap();
            i = 2;
        } else if !c.is_empty() && al(c[0]).is_some() {
            sp.align = al(c[0]).unwrap();
            i = 1;
        }
        if i < c.len() && c[i] == '+' {
            sp.plus = true;
            i += 1;
        }
        if i < c.len() && c[i] == '#' {
            sp.alternate = true;
            i += 1;
        }
        if i < c.len() && c[i] == '0' {
            sp.zero = true;
            i += 1;
        }
        let mut w = String::new();
        while i < c.len() && c[i].is_ascii_digit() {
            w.push(c[i]);
            i += 1;
        }
        if !w.is_empty() {
            sp.width = Count::Is(w.parse().unwrap());
        }
        if i < c.len() && c[i] == '.' {
            i += 1;
            let mut p = String::new();
            while i < c.len() && c[i].is_ascii_digit() {
                p.push(c[i]);
                i += 1;
            }
            sp.precision = Count::Is(p.parse().unwrap());
        }
        let ty: String = c[i..].iter().collect();
        sp.tr = match ty.as_str() {
            "" => Trait::Display,
            "?" => Trait::Debug,
            "x?" => Trait::DebugLowerHex,
            "X?" => Trait::DebugUpperHex,
            "x" => Trait::LowerHex,
            "X" => Trait::UpperHex,
            "o" => Trait::Octal,
            "b" => Trait::Binary,
            "e" => Trait::LowerExp,
            "E" => Trait::UpperExp,
            other => panic!("{other}"),
        };
        sp
    }

    fn one(kind: ValueKind, size: u8, s: &str, slot: u64) -> String {
        render(&arg(kind, size, spec(s)), &[slot], |_, _| None)
    }

    /// Every leaf kind against Rust's own `format!` with the same literal spec.
    #[test]
    fn leaves_match_rust_formatting() {
        macro_rules! check {
            ($kind:expr, $size:expr, $slot:expr, $v:expr, [$($s:literal),*]) => {
                $(
                    assert_eq!(
                        one($kind, $size, $s, $slot),
                        format!(concat!("{:", $s, "}"), $v),
                        "spec {{:{}}} of {:?}", $s, $v
                    );
                )*
            };
        }
        let specs_int = [
            "", "5", "<5", "^5", ">5", "*^7", "+", "+05", "05", "#x", "#010x", "#X", "x", "X", "o",
            "#o", "b", "#b", "e", "E", "?", "5?", "x?", "#x?", "X?", "08?", "-^9",
        ];
        let _ = specs_int;
        check!(
            ValueKind::Int,
            4,
            (-42i32) as u32 as u64,
            -42i32,
            [
                "", "5", "<5", "^5", ">5", "*^7", "+", "+05", "05", "#x", "#010x", "#X", "x", "X",
                "o", "#o", "b", "#b", "e", "E", "?", "5?", "x?", "#x?", "X?", "08?", "-^9", ".3"
            ]
        );
        check!(
            ValueKind::Int,
            1,
            (-1i8) as u8 as u64,
            -1i8,
            ["x", "#b", "o", "5", "+"]
        );
        check!(
            ValueKind::Int,
            2,
            (-300i16) as u16 as u64,
            -300i16,
            ["X", "08"]
        );
        check!(
            ValueKind::Uint,
            4,
            255,
            255u32,
            ["", "#010x", "+", "e", "^6"]
        );
        check!(ValueKind::Uint, 8, u64::MAX, u64::MAX, ["", "x", "25", "e"]);
        check!(
            ValueKind::Int,
            8,
            i64::MIN as u64,
            i64::MIN,
            ["", "x", "+", "030"]
        );
        check!(
            ValueKind::F32,
            0,
            1.5f32.to_bits() as u64,
            1.5f32,
            [
                "", "?", ".2", "8.3", "<8.3", "^9.1", "+", "+08.2", "e", "E", ".3e", "10?", "#?",
                "08?"
            ]
        );
        check!(
            ValueKind::F32,
            0,
            (-0.0f32).to_bits() as u64,
            -0.0f32,
            ["", "?", "+", "05"]
        );
        check!(
            ValueKind::F32,
            0,
            f32::NAN.to_bits() as u64,
            f32::NAN,
            ["", "05", "+", "?"]
        );
        check!(
            ValueKind::F32,
            0,
            f32::INFINITY.to_bits() as u64,
            f32::INFINITY,
            ["08", "-^8", "?"]
        );
        check!(
            ValueKind::F32,
            0,
            1e20f32.to_bits() as u64,
            1e20f32,
            ["", "?", "e"]
        );
        check!(
            ValueKind::F64,
            0,
            (1.0f64 / 3.0).to_bits(),
            1.0f64 / 3.0,
            ["", "?", ".5", "12.4e", "E"]
        );
        check!(
            ValueKind::Bool,
            0,
            1,
            true,
            ["", "?", "6", ">6", "^7?", "06"]
        );
        check!(
            ValueKind::Char,
            0,
            'é' as u64,
            'é',
            ["", "?", "4", "*>4", "4?"]
        );
        check!(ValueKind::Unit, 0, 0, (), ["?", "08?", ">4?"]);
    }

    #[test]
    fn strings_and_counts_from_slots() {
        let mut t = Vec::new();
        push_text("[", &mut t);
        let mut s = spec("");
        s.width = Count::Slot;
        s.precision = Count::Slot;
        s.align = Align::Right;
        s.fill = 'é';
        s.encode(ValueKind::Str, 0, &mut t);
        push_text("]", &mut t);
        let out = render(&t, &[8, 2, 0x1000 | (5u64 << 32)], |a, l| {
            (a == 0x1000 && l == 5).then(|| b"hello".to_vec())
        });
        assert_eq!(out, format!("[{:é>8.2}]", "hello"));
        assert_eq!(
            render(&arg(ValueKind::Str, 0, spec("?")), &[0x40], |_, _| None),
            "<unreadable string at 0x00000040>"
        );
        assert_eq!(
            render(&arg(ValueKind::Int, 4, spec("")), &[], |_, _| None),
            "<missing argument>"
        );
        let mut nul = Vec::new();
        push_text("a\0b", &mut nul);
        assert_eq!(render(&nul, &[], |_, _| None), "a\0b");
    }

    /// Descriptor-driven `{:?}`/`{:#?}` of nested structs, enums, tuples, arrays.
    #[test]
    fn described_values_match_derived_debug() {
        #[derive(Debug)]
        #[allow(dead_code)]
        struct P {
            x: f32,
            tag: Option<u8>,
            pair: (i32, bool),
            arr: [u16; 2],
        }
        // Memory: P at 0x100: x f32 @0, tag {u8 tag, u8 payload} @4, pair @8 (i32, bool) , arr @16.
        let mut mem = [0u8; 64];
        mem[0..4].copy_from_slice(&2.5f32.to_le_bytes());
        mem[4] = 1;
        mem[5] = 7;
        mem[8..12].copy_from_slice(&(-3i32).to_le_bytes());
        mem[12] = 1;
        mem[16..18].copy_from_slice(&10u16.to_le_bytes());
        mem[18..20].copy_from_slice(&65535u16.to_le_bytes());
        let mut d = Vec::new();
        let s16 = |d: &mut Vec<u8>, s: &str| {
            d.extend_from_slice(&(s.len() as u16).to_le_bytes());
            d.extend_from_slice(s.as_bytes());
        };
        d.push(desc::STRUCT);
        s16(&mut d, "P");
        d.extend_from_slice(&4u16.to_le_bytes());
        s16(&mut d, "x");
        d.extend_from_slice(&0u32.to_le_bytes());
        d.push(desc::F32);
        s16(&mut d, "tag");
        d.extend_from_slice(&4u32.to_le_bytes());
        d.push(desc::ENUM);
        d.extend_from_slice(&0u32.to_le_bytes());
        d.push(1);
        d.push(0);
        d.extend_from_slice(&2u16.to_le_bytes());
        d.extend_from_slice(&0i64.to_le_bytes());
        d.push(desc::UNIT_STRUCT);
        s16(&mut d, "None");
        d.extend_from_slice(&1i64.to_le_bytes());
        d.push(desc::TUPLE_STRUCT);
        s16(&mut d, "Some");
        d.extend_from_slice(&1u16.to_le_bytes());
        d.extend_from_slice(&1u32.to_le_bytes());
        d.push(desc::UINT);
        d.push(1);
        s16(&mut d, "pair");
        d.extend_from_slice(&8u32.to_le_bytes());
        d.push(desc::TUPLE);
        d.extend_from_slice(&2u16.to_le_bytes());
        d.extend_from_slice(&0u32.to_le_bytes());
        d.push(desc::INT);
        d.push(4);
        d.extend_from_slice(&4u32.to_le_bytes());
        d.push(desc::BOOL);
        s16(&mut d, "arr");
        d.extend_from_slice(&16u32.to_le_bytes());
        d.push(desc::ARRAY);
        d.extend_from_slice(&2u32.to_le_bytes());
        d.extend_from_slice(&2u32.to_le_bytes());
        d.push(desc::UINT);
        d.push(2);
        let mut blob = (d.len() as u32).to_le_bytes().to_vec();
        blob.extend_from_slice(&d);
        let read = |a: u32, l: u32| -> Option<Vec<u8>> {
            if a >= 0x100 && a + l <= 0x100 + 64 {
                Some(mem[(a - 0x100) as usize..(a - 0x100 + l) as usize].to_vec())
            } else if a >= 0x8000 && a + l <= 0x8000 + blob.len() as u32 {
                Some(blob[(a - 0x8000) as usize..(a - 0x8000 + l) as usize].to_vec())
            } else {
                None
            }
        };
        let v = P {
            x: 2.5,
            tag: Some(7),
            pair: (-3, true),
            arr: [10, 65535],
        };
        let slot = 0x100u64 | (0x8000u64 << 32);
        for s in ["?", "#?", "8?", "x?", "#x?", "+.1?"] {
            let got = render(&arg(ValueKind::Described, 0, spec(s)), &[slot], read);
            let want = match s {
                "?" => format!("{v:?}"),
                "#?" => format!("{v:#?}"),
                "8?" => format!("{v:8?}"),
                "x?" => format!("{v:x?}"),
                "#x?" => format!("{v:#x?}"),
                _ => format!("{v:+.1?}"),
            };
            assert_eq!(got, want, "{s}");
        }
    }
}
