// A `move` closure takes the value; the caller cannot use it afterwards.
struct Tile {
    x: u32,
}

fn width(t: &Tile) -> u32 {
    t.x
}

fn trax_main() {
    let t = Tile { x: 3 };
    let f = move || width(&t) + 1;
    println!("{}", f());
    println!("{}", t.x); //~ E0382
}
