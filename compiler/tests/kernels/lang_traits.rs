//! TRaX-Rust language suite, part 2: generic functions, structs and impls with trait
//! bounds; user traits (static dispatch, default methods, associated consts and types,
//! supertraits, impls for primitives); derives; `impl Default`; `Index`/`IndexMut`;
//! `PartialEq`/`PartialOrd` impls and `#[derive(PartialOrd)]` (structs, tuple structs,
//! generic structs, fieldless enums with explicit discriminants, enums with data; NaN
//! fields); operator traits on generic types; type aliases; nested items; `const fn` in
//! `const`/`static` initializers.

use std::ops::{Add, Index, IndexMut, Mul, Neg, Sub};

/// A float type the helpers are generic over.
trait Float: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + PartialOrd {
    const ZERO: Self;
    const ONE: Self;
    fn sqrt(self) -> Self;
    fn from_f32(v: f32) -> Self;
    fn to_f64(self) -> f64;
    /// Default method using required ones.
    fn lerp(self, b: Self, t: Self) -> Self {
        self + (b - self) * t
    }
}

impl Float for f32 {
    const ZERO: f32 = 0.0;
    const ONE: f32 = 1.0;
    fn sqrt(self) -> f32 {
        f32::sqrt(self)
    }
    fn from_f32(v: f32) -> f32 {
        v
    }
    fn to_f64(self) -> f64 {
        self as f64
    }
}

impl Float for f64 {
    const ZERO: f64 = 0.0;
    const ONE: f64 = 1.0;
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
    fn from_f32(v: f32) -> f64 {
        v as f64
    }
    fn to_f64(self) -> f64 {
        self
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Default)]
struct V2<T> {
    x: T,
    y: T,
}

impl<T: Float> V2<T> {
    fn new(x: T, y: T) -> Self {
        V2 { x, y }
    }
    fn dot(self, o: V2<T>) -> T {
        self.x * o.x + self.y * o.y
    }
    fn length(self) -> T {
        self.dot(self).sqrt()
    }
}

impl<T: Float> Add for V2<T> {
    type Output = V2<T>;
    fn add(self, o: V2<T>) -> V2<T> {
        V2::new(self.x + o.x, self.y + o.y)
    }
}

impl<T: Float> Mul<T> for V2<T> {
    type Output = V2<T>;
    fn mul(self, s: T) -> V2<T> {
        V2::new(self.x * s, self.y * s)
    }
}

impl Neg for V2<f32> {
    type Output = V2<f32>;
    fn neg(self) -> V2<f32> {
        V2::new(-self.x, -self.y)
    }
}

fn max_of<T: PartialOrd + Copy>(xs: &[T]) -> T {
    let mut m = xs[0];
    for &x in xs.iter() {
        if x > m {
            m = x;
        }
    }
    m
}

fn norm<T: Float>(a: T, b: T) -> T {
    (a * a + b * b).sqrt()
}

/// Shapes with an associated type and const.
trait Shape {
    type Measure: Copy;
    const SIDES: u32;
    fn area(&self) -> f32;
    fn measure(&self) -> Self::Measure;
    fn describe(&self) -> f32 {
        self.area() * Self::SIDES as f32
    }
}

/// A supertrait.
trait Named: Shape {
    fn id(&self) -> u32;
}

#[derive(Clone, Copy, Debug)]
struct Square {
    side: f32,
}

#[derive(Clone, Copy, Debug)]
struct Tri {
    base: f32,
    height: f32,
}

impl Shape for Square {
    type Measure = f32;
    const SIDES: u32 = 4;
    fn area(&self) -> f32 {
        self.side * self.side
    }
    fn measure(&self) -> f32 {
        self.side
    }
}

impl Shape for Tri {
    type Measure = (f32, f32);
    const SIDES: u32 = 3;
    fn area(&self) -> f32 {
        0.5 * self.base * self.height
    }
    fn measure(&self) -> (f32, f32) {
        (self.base, self.height)
    }
    fn describe(&self) -> f32 {
        -1.0
    }
}

impl Named for Square {
    fn id(&self) -> u32 {
        Self::SIDES * 10
    }
}

fn total_area<S: Shape>(shapes: &[S]) -> f32 {
    let mut t = 0.0;
    for s in shapes {
        t += s.area();
    }
    t
}

fn sides_of<S: Shape>(_s: &S) -> u32 {
    S::SIDES
}

fn name_and_area<N>(n: &N) -> (u32, f32)
where
    N: Named,
{
    (n.id(), n.describe())
}

/// A counter trait implemented for a primitive.
trait Bump {
    fn bump(self) -> Self;
}

impl Bump for u32 {
    fn bump(self) -> u32 {
        self + 1
    }
}

/// A fixed-size grid with `Index`/`IndexMut` by `(row, col)`.
#[derive(Clone, Copy, Debug, Default)]
struct Grid {
    cells: [u16; 6],
}

impl Index<(usize, usize)> for Grid {
    type Output = u16;
    fn index(&self, (r, c): (usize, usize)) -> &u16 {
        &self.cells[r * 3 + c]
    }
}

impl IndexMut<(usize, usize)> for Grid {
    fn index_mut(&mut self, (r, c): (usize, usize)) -> &mut u16 {
        &mut self.cells[r * 3 + c]
    }
}

/// Ordering by distance only.
#[derive(Clone, Copy, Debug)]
struct Dist {
    t: f32,
    tag: u32,
}

impl PartialEq for Dist {
    fn eq(&self, o: &Dist) -> bool {
        self.t == o.t
    }
}

impl PartialOrd for Dist {
    fn partial_cmp(&self, o: &Dist) -> Option<std::cmp::Ordering> {
        self.t.partial_cmp(&o.t)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Settings {
    spp: u32,
    gamma: f32,
    on: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            spp: 4,
            gamma: 2.2,
            on: true,
        }
    }
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
enum Mode {
    #[default]
    Fast,
    Slow,
}

#[derive(Clone, Copy, Debug, Default)]
struct Config {
    settings: Settings,
    mode: Mode,
    scale: (f32, u8),
    ids: [u32; 3],
}

type Real = f32;
type Vec2f = V2<Real>;
type Pair<T> = (T, T);

const fn square(x: u32) -> u32 {
    x * x
}

const fn tri_number(n: u32) -> u32 {
    let mut s = 0;
    let mut i = 1;
    while i <= n {
        s += i;
        i += 1;
    }
    s
}

const AREA: u32 = square(7) + 1;
static TRI: u32 = tri_number(10);
const TABLE: [u32; 4] = [square(1), square(2), square(3), tri_number(4)];

fn swap_pair<T: Copy>(p: Pair<T>) -> Pair<T> {
    (p.1, p.0)
}

/// Derived ordering: fields in declaration order.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
struct Key {
    depth: u32,
    t: f32,
}

#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
struct Wrap<T>(T, u8);

/// Fieldless: ordered by discriminant, not by declaration.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
enum Level {
    High = 10,
    Low = 1,
    Mid = 5,
}

/// With data: by variant, then by the variant's fields.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
enum Prim {
    Point,
    Disk(f32),
    Box { w: u32, h: Level },
}

fn trax_main() {
    let keys = [
        Key { depth: 1, t: 2.0 },
        Key { depth: 1, t: 3.0 },
        Key { depth: 0, t: 9.0 },
        Key { depth: 1, t: f32::NAN },
    ];
    for a in keys.iter() {
        for b in keys.iter() {
            print!("{:?}{}{} ", a.partial_cmp(b), (a < b) as u8, (a >= b) as u8);
        }
    }
    println!();
    println!(
        "wrap {:?} {} {}",
        Wrap(2.5f64, 1).partial_cmp(&Wrap(2.5, 0)),
        Wrap(-1i16, 9) < Wrap(3, 0),
        Wrap('a', 0) <= Wrap('a', 0)
    );
    println!(
        "level {} {} {:?}",
        Level::High > Level::Mid,
        Level::Low < Level::Mid,
        Level::Mid.partial_cmp(&Level::Mid)
    );
    let shapes = [
        Prim::Point,
        Prim::Disk(1.0),
        Prim::Disk(f32::NAN),
        Prim::Box { w: 2, h: Level::Low },
        Prim::Box { w: 2, h: Level::High },
        Prim::Disk(0.5),
    ];
    for a in shapes.iter() {
        for b in shapes.iter() {
            print!("{:?} ", a.partial_cmp(b));
        }
    }
    println!();

    if trax::global_id() != 0 {
        return;
    }
    // Generic functions over f32 and f64.
    println!("norm {} {}", norm(3.0f32, 4.0), norm(1.0f64, 1.0));
    println!("lerp {} {}", 2.0f32.lerp(4.0, 0.25), Float::lerp(1.0f64, 3.0, 0.5));
    println!("consts {} {} {}", f32::ONE + f32::ZERO, <f64 as Float>::ONE, f32::from_f32(1.5).to_f64());
    println!("max {} {} {}", max_of(&[3, 9, 2]), max_of(&[1.5f32, -2.0]), max_of(&['a', 'z', 'm']));
    // Generic structs, impls and operators.
    let a: Vec2f = V2::new(3.0, 4.0);
    let b = V2::<f64>::new(1.0, 2.0);
    println!("v2 {:?} {:?} len {} {}", a, b, a.length(), b.length());
    println!("ops {:?} {:?} {:?}", a + a, b * 2.0, -a);
    println!("default {:?} eq {}", V2::<f32>::default(), a == V2 { x: 3.0, y: 4.0 });
    // Traits with associated types and consts, static dispatch, default methods.
    let sq = [Square { side: 2.0 }, Square { side: 3.0 }];
    let tr = Tri {
        base: 4.0,
        height: 1.5,
    };
    println!("areas {} {} {}", total_area(&sq), total_area(&[tr]), sq[0].area());
    println!("describe {} {} sides {} {}", sq[1].describe(), tr.describe(), sides_of(&sq[0]), sides_of(&tr));
    println!("measure {:?} {:?}", sq[0].measure(), tr.measure());
    println!("named {:?} {}", name_and_area(&sq[1]), <Square as Shape>::SIDES);
    println!("bump {}", 41u32.bump());
    // Index/IndexMut.
    let mut g = Grid::default();
    g[(1, 2)] = 7;
    g[(0, 0)] += 2;
    println!("grid {} {} {:?}", g[(1, 2)], g[(0, 0)], g);
    // PartialEq/PartialOrd impls drive comparisons.
    let d1 = Dist { t: 1.0, tag: 1 };
    let d2 = Dist { t: 2.0, tag: 2 };
    let d3 = Dist { t: 1.0, tag: 3 };
    println!("cmp {} {} {} {} {} {}", d1 < d2, d2 > d1, d1 <= d3, d1 == d3, d1 != d2, d2 >= d2);
    println!("partial_cmp {:?} {:?}", d1.partial_cmp(&d2), 1.0f32.partial_cmp(&f32::NAN));
    // Default: impl, derive (with a #[default] variant), nested defaults.
    let s = Settings::default();
    let c: Config = Default::default();
    println!("settings {:?} {:?}", s, Mode::default());
    println!("config {:?}", c);
    let c2 = Config {
        mode: Mode::Slow,
        ..Default::default()
    };
    println!("config2 {:?} {}", c2.mode, c2.settings == s);
    // Type aliases.
    let pr: Pair<u8> = (1, 2);
    println!("alias {:?} {:?}", swap_pair(pr), swap_pair((0.5f32, -0.5f32)));
    // Nested items.
    fn helper(x: u32) -> u32 {
        const K: u32 = 3;
        x * K
    }
    #[derive(Debug)]
    struct Local {
        v: u32,
    }
    let l = Local { v: helper(5) };
    println!("nested {:?} {}", l, l.v);
    // const fn in const/static initializers.
    println!("const {} {} {:?}", AREA, TRI, TABLE);
    let mut total = 0;
    for i in 0..4 {
        total += TABLE[i];
    }
    println!("table sum {} {}", total, square(12));
}
