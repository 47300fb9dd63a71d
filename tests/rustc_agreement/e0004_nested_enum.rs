// A nested variant left out.
#[derive(Clone, Copy)]
enum Axis {
    X,
    Y,
    Z,
}

#[derive(Clone, Copy)]
enum Split {
    Leaf,
    Inner(Axis),
}

fn code(s: Split) -> u32 {
    match s { //~ E0004
        Split::Leaf => 0,
        Split::Inner(Axis::X) => 1,
        Split::Inner(Axis::Y) => 2,
    }
}

fn trax_main() {
    println!("{}", code(Split::Inner(Axis::Z)));
}
