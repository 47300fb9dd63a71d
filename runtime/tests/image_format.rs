//! The memory-image type and its file format: segments keep names, permissions and zero
//! tails through a round trip, and every broken rule is an error naming the segment.

use trax_runtime::image::{ImageError, MemoryImage, Perms, Segment};

fn image() -> MemoryImage {
    MemoryImage {
        segments: vec![
            Segment::new("scene_header", 0x1_0000, vec![1, 2, 3, 4], Perms::R),
            Segment::new("text", 0x10_0000, vec![9; 10], Perms::RX),
            Segment {
                name: "framebuffer".into(),
                addr: 0x20_0000,
                data: vec![7; 3],
                size: 0x100,
                perms: Perms::RW,
            },
        ],
    }
}

#[test]
fn round_trip_keeps_names_permissions_and_zero_tails() {
    let img = image();
    let back = MemoryImage::parse(&img.to_bytes()).unwrap();
    assert_eq!(back, img);
    assert_eq!(back.segment("text").unwrap().perms, Perms::RX);
    assert_eq!(back.read(0x20_0002, 2), Some(vec![7, 0]));
    assert_eq!(back.read_u32(0x20_00fc), Some(0));
    assert_eq!(back.read(0x20_00fe, 4), None, "past the end");
    assert_eq!(back.read_u32(0x1_0000), Some(0x0403_0201));
    assert_eq!(back.segment_at(0x10_0009, 1).unwrap().name, "text");
    assert_eq!(
        format!("{} {} {}", Perms::RX, Perms::RW, Perms::R | Perms::X),
        "r-x rw- r-x"
    );
    assert_eq!(Perms::from_elf(0x6), Perms::RW);
}

#[test]
fn rejects_broken_images() {
    let err = |b: &[u8]| MemoryImage::parse(b).unwrap_err().to_string();
    assert!(err(b"TRAXIMG1\0\0\0\0").contains("version 2"));
    let mut b = image().to_bytes();
    b.truncate(b.len() - 1);
    assert!(matches!(
        MemoryImage::parse(&b),
        Err(ImageError::Truncated { .. })
    ));
    let mut b = image().to_bytes();
    b.push(0);
    assert!(matches!(
        MemoryImage::parse(&b),
        Err(ImageError::Trailing { len: 1 })
    ));
    let check = |img: MemoryImage, index: usize, what: &str| {
        let e = MemoryImage::parse(&img.to_bytes()).unwrap_err();
        assert!(
            matches!(e, ImageError::BadSegment { index: i, .. } if i == index),
            "{e}"
        );
        assert!(e.to_string().contains(what), "{e}");
        assert!(img.validate().is_err());
    };
    let mut overlap = image();
    overlap.segments[2].addr = 0x10_0008;
    check(overlap, 2, "overlaps");
    let mut long = image();
    long.segments[1].data = vec![0; 11];
    check(long, 1, "more data than its size");
    let mut wrap = image();
    wrap.segments[2].addr = 0xffff_ff80;
    check(wrap, 2, "32-bit");
    let mut name = image();
    name.segments[0].name = "n".repeat(256);
    check(name, 0, "name");
    // Unknown permission bits in a file.
    let mut b = image().to_bytes();
    b[12 + 8] = 9;
    assert!(err(&b).contains("permission"), "{}", err(&b));
}
