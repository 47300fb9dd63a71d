// Moving a value out while a reference to it is alive.
struct Mesh {
    tris: u32,
}

fn drop_mesh(m: Mesh) -> u32 {
    m.tris
}

fn trax_main() {
    let m = Mesh { tris: 12 };
    let r = &m;
    let n = drop_mesh(m); //~ E0505
    println!("{} {}", r.tris, n);
}
