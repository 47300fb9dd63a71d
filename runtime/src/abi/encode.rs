//! How contract types become bytes. Every field of a contract struct is a 4-byte
//! little-endian word (`u32`, `f32`), an array of such fields or another contract struct,
//! so a `#[repr(C)]` contract struct has no padding and writing its fields one after the
//! other in declaration order *is* its in-memory layout (each struct asserts at compile time
//! that its size is the sum of its fields'). [`Field`] is that encoding; [`StructLayout`]
//! describes a struct field by field (names, kinds, dimensions, offsets, docs) for the
//! renderers of the prelude's `layout.rs` and the C header.

/// A scalar of simulated memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scalar {
    /// 32-bit unsigned integer.
    U32,
    /// IEEE 754 single.
    F32,
}

impl Scalar {
    /// The C type (`<stdint.h>` names).
    pub fn c_type(self) -> &'static str {
        match self {
            Scalar::U32 => "uint32_t",
            Scalar::F32 => "float",
        }
    }

    /// The Rust type.
    pub fn rust_type(self) -> &'static str {
        match self {
            Scalar::U32 => "u32",
            Scalar::F32 => "f32",
        }
    }
}

/// What a field (or a component element) is made of, innermost.
#[derive(Clone, Copy, Debug)]
pub enum Kind {
    /// A scalar (or array of scalars).
    Scalar(Scalar),
    /// A contract struct (or array of them), described by its layout function.
    Struct(fn() -> StructLayout),
}

impl Kind {
    /// The C type name (`float`, `uint32_t`, `trax_camera_t`).
    pub fn c_type(&self) -> &'static str {
        match self {
            Kind::Scalar(s) => s.c_type(),
            Kind::Struct(l) => l().c_name,
        }
    }

    /// The Rust type name (`f32`, `Camera`).
    pub fn rust_type(&self) -> &'static str {
        match self {
            Kind::Scalar(s) => s.rust_type(),
            Kind::Struct(l) => l().name,
        }
    }
}

/// A type stored in simulated memory, encoded as little-endian 4-byte words.
pub trait Field: Copy + Default {
    /// The innermost kind.
    const KIND: Kind;
    /// Array dimensions, outermost first (empty for a scalar or a struct).
    fn dims() -> Vec<usize> {
        Vec::new()
    }
    /// Appends the value's bytes as laid out in memory.
    fn put(&self, out: &mut Vec<u8>);
    /// Reads a value from the start of `b`, which holds at least `size_of::<Self>()`
    /// bytes (see [`decode`] for a checked read).
    fn get(b: &[u8]) -> Self;
    /// The value's bytes.
    fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(std::mem::size_of::<Self>());
        self.put(&mut out);
        out
    }
}

/// A contract struct: a [`Field`] with a described layout.
pub trait Struct: Field {
    /// Its layout, field by field.
    fn layout() -> StructLayout;
}

impl Field for u32 {
    const KIND: Kind = Kind::Scalar(Scalar::U32);
    fn put(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
    fn get(b: &[u8]) -> Self {
        u32::from_le_bytes([b[0], b[1], b[2], b[3]])
    }
}

impl Field for f32 {
    const KIND: Kind = Kind::Scalar(Scalar::F32);
    fn put(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_bits().to_le_bytes());
    }
    fn get(b: &[u8]) -> Self {
        f32::from_bits(u32::get(b))
    }
}

impl<T: Field, const N: usize> Field for [T; N]
where
    [T; N]: Default,
{
    const KIND: Kind = T::KIND;
    fn dims() -> Vec<usize> {
        let mut d = vec![N];
        d.extend(T::dims());
        d
    }
    fn put(&self, out: &mut Vec<u8>) {
        for x in self {
            x.put(out);
        }
    }
    fn get(b: &[u8]) -> Self {
        let n = std::mem::size_of::<T>();
        std::array::from_fn(|i| T::get(&b[i * n..]))
    }
}

/// Encodes elements one after another, as a component stores them.
pub fn encode<T: Field>(items: impl IntoIterator<Item = T>) -> Vec<u8> {
    let mut out = Vec::new();
    for x in items {
        x.put(&mut out);
    }
    out
}

/// Reads a `T` from the start of `b`, if `b` is long enough.
pub fn decode<T: Field>(b: &[u8]) -> Option<T> {
    (b.len() >= std::mem::size_of::<T>()).then(|| T::get(b))
}

/// The layout of a contract struct.
#[derive(Clone, Debug)]
pub struct StructLayout {
    /// Rust name (`Camera`).
    pub name: &'static str,
    /// C name (`trax_camera_t`).
    pub c_name: &'static str,
    /// Prefix of its constants in the prelude's `layout.rs` (`CAM` → `CAM_EYE`, `CAM_SIZE`).
    pub prefix: &'static str,
    /// Doc comment.
    pub doc: &'static str,
    /// Size in bytes.
    pub size: usize,
    /// Fields in declaration (and memory) order.
    pub fields: Vec<FieldLayout>,
}

/// One field of a [`StructLayout`].
#[derive(Clone, Debug)]
pub struct FieldLayout {
    /// Name.
    pub name: &'static str,
    /// Innermost kind.
    pub kind: Kind,
    /// Array dimensions, outermost first.
    pub dims: Vec<usize>,
    /// Byte offset in the struct.
    pub offset: usize,
    /// Size in bytes.
    pub size: usize,
    /// Doc comment.
    pub doc: &'static str,
}

impl StructLayout {
    /// The field called `name`.
    pub fn field(&self, name: &str) -> Option<&FieldLayout> {
        self.fields.iter().find(|f| f.name == name)
    }
}

/// Defines a `#[repr(C)]` contract struct: the struct, its [`Field`] encoding (fields in
/// declaration order), its [`StructLayout`] and compile-time checks that it has no padding
/// and 4-byte alignment. Field docs must be `///` comments (they are copied into the layout).
macro_rules! contract_struct {
    (
        $(#[doc = $doc:literal])*
        pub struct $name:ident as $cname:literal, prefix $prefix:literal {
            $( $(#[doc = $fdoc:literal])* pub $field:ident : $fty:ty, )*
        }
    ) => {
        $(#[doc = $doc])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        pub struct $name {
            $( $(#[doc = $fdoc])* pub $field: $fty, )*
        }

        // No padding and word alignment: the field-by-field encoding is the layout.
        const _: () = assert!(std::mem::size_of::<$name>() == 0 $( + std::mem::size_of::<$fty>() )*);
        const _: () = assert!(std::mem::align_of::<$name>() == 4);

        impl $crate::abi::encode::Field for $name {
            const KIND: $crate::abi::encode::Kind =
                $crate::abi::encode::Kind::Struct(<$name as $crate::abi::encode::Struct>::layout);
            fn put(&self, out: &mut Vec<u8>) {
                $( $crate::abi::encode::Field::put(&self.$field, out); )*
            }
            fn get(b: &[u8]) -> Self {
                $name {
                    $( $field: <$fty as $crate::abi::encode::Field>::get(
                        &b[std::mem::offset_of!($name, $field)..],
                    ), )*
                }
            }
        }

        impl $crate::abi::encode::Struct for $name {
            fn layout() -> $crate::abi::encode::StructLayout {
                $crate::abi::encode::StructLayout {
                    name: stringify!($name),
                    c_name: $cname,
                    prefix: $prefix,
                    doc: concat!($($doc, "\n",)*),
                    size: std::mem::size_of::<$name>(),
                    fields: vec![$(
                        $crate::abi::encode::FieldLayout {
                            name: stringify!($field),
                            kind: <$fty as $crate::abi::encode::Field>::KIND,
                            dims: <$fty as $crate::abi::encode::Field>::dims(),
                            offset: std::mem::offset_of!($name, $field),
                            size: std::mem::size_of::<$fty>(),
                            doc: concat!($($fdoc, "\n",)*),
                        },
                    )*],
                }
            }
        }
    };
}
