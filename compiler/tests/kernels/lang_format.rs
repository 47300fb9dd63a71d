//! TRaX-Rust language suite, part 4: `print!` format specs — width, fill, alignment,
//! sign, `#`, `0`, precision (literal, `N$`, `name$`, `.*`), `{:x}`/`{:X}`/`{:o}`/`{:b}`/
//! `{:e}`/`{:E}`, `{:?}`/`{:#?}` of numbers, strings, chars, structs, enums, tuples,
//! arrays, slices, `Option`, `Result`, references; named, indexed and captured arguments.

#[derive(Clone, Copy, Debug, PartialEq)]
enum Shape {
    Point,
    Circle { r: f32 },
    Rect(f32, f32),
}

#[derive(Clone, Copy, Debug)]
struct Ray {
    origin: (f32, f32, f32),
    dir: [f32; 3],
    depth: u8,
    tag: char,
    name: &'static str,
    shape: Shape,
    hit: Option<u32>,
}

#[derive(Clone, Copy, Debug)]
struct Wrap(i64, bool);

#[derive(Clone, Copy, Debug)]
struct Empty;

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    let x = 3.14159f32;
    let n = -42i32;
    let u = 255u32;
    let big = 1u64 << 40;
    println!("[{}] [{:8}] [{:<8}] [{:^8}] [{:>8}] [{:*^9}] [{:08.3}]", x, x, x, x, x, x, x);
    println!("[{:.0}] [{:.1}] [{:.5}] [{:+.2}] [{:e}] [{:E}] [{:.2e}]", x, x, x, x, x, 0.00012f64, 123456.0f32);
    println!("[{}] [{:5}] [{:<5}] [{:^5}] [{:05}] [{:+}] [{:+05}]", n, n, n, n, n, 7, 7);
    println!("[{:x}] [{:X}] [{:#x}] [{:#010x}] [{:o}] [{:#o}] [{:b}] [{:#b}] [{:08b}]", u, u, u, u, u, u, 5u8, 5u8, 5u8);
    println!("[{:x}] [{:x}] [{:X}] [{:b}] [{:e}]", n, -1i8, -2i16, -1i8, 1500);
    println!("[{}] [{:x}] [{:e}] [{}] [{}]", big, big, big, i64::MIN, u64::MAX);
    println!("[{:?}] [{:?}] [{:?}] [{:?}] [{:?}]", 1.0f32, 0.1f64, 1e20f32, -0.0f32, f32::NAN);
    println!("[{}] [{}] [{:?}] [{:?}]", f32::INFINITY, -f64::INFINITY, f32::MIN_POSITIVE, f64::MAX);
    println!("[{:?}] [{:?}] [{:?}] [{:>6?}] [{:x?}] [{:#X?}]", "q\"\n", 'c', '\'', true, 255u8, 255u8);
    println!("[{:6}] [{:<6}] [{:>6}] [{:^6}] [{:.2}] [{:-^8.3}]", "ab", "ab", "ab", "ab", "abcdef", "abcdef");
    println!("[{:3}] [{:>4}] [{:<5}] [{:^7}]", 'x', true, false, 'é');
    // Width and precision from arguments.
    let w = 10;
    let p = 2;
    println!("[{:w$}] [{:>w$.p$}] [{:.*}] [{:>5$.6$}]", x, x, 3, x, x, 12, 1);
    println!("[{0}-{0}] [{1:?}] [{name}] [{name:>6}] [{x:.1}] [{n:+}]", 5, "s", name = "nm");
    // Composite values with {:?} and {:#?}.
    let r = Ray {
        origin: (0.0, 1.5, -2.0),
        dir: [0.0, 0.0, 1.0],
        depth: 3,
        tag: 'r',
        name: "primary",
        shape: Shape::Circle { r: 0.5 },
        hit: Some(17),
    };
    println!("{:?}", r);
    println!("{:#?}", r);
    println!("{:?} {:?} {:?}", Shape::Point, Shape::Rect(1.0, 2.5), Wrap(-9, true));
    println!("{:?} {:?} {:?}", Empty, (1,), ((1u8, 'a'), [2i16, -3]));
    let arr = [Shape::Point, Shape::Rect(0.5, 0.25)];
    let sl: &[Shape] = &arr;
    println!("{:?} {:?} {:?}", arr, sl, &sl[1..]);
    let none: Option<f32> = None;
    let ok: Result<u32, i8> = Ok(4);
    let err: Result<u32, i8> = Err(-1);
    println!("{:?} {:?} {:?} {:?} {:?}", Some(1.5f32), none, ok, err, Some(Some(())));
    println!("{:5?}|{:<8?}|{:+.1?}|{:#x?}", Some(1), Wrap(2, false), (1.0f32, -2.0f64), [10u16, 255]);
    println!("{:#?}", (Some(Shape::Rect(1.0, 2.0)), [1u8; 2]));
    let rr = &r;
    println!("{:?} {:?}", rr.shape, &&rr.hit);
    print!("no newline ");
    print!("{}{}", 1, 2);
    println!();
    println!("{{literal}} {} {{}}", 0);
}
