// `let Some(x) = ...` without `else`.
fn find(a: &[u32], v: u32) -> Option<usize> {
    let mut i = 0;
    while i < a.len() {
        if a[i] == v {
            return Some(i);
        }
        i += 1;
    }
    None
}

fn trax_main() {
    let a = [3u32, 4, 5];
    let Some(i) = find(&a, 4); //~ E0005
    println!("{}", i);
}
