// A returned reference whose lifetime cannot be inferred.
fn longer(a: &[u32], b: &[u32]) -> &[u32] { //~ E0106
    if a.len() > b.len() {
        a
    } else {
        b
    }
}

fn trax_main() {
    let a = [1u32, 2];
    let b = [3u32];
    println!("{}", longer(&a, &b).len());
}
