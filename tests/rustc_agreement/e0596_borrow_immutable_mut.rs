// `&mut` of a variable not declared `mut`.
fn fill(a: &mut [u32; 3]) {
    a[0] = 1;
}

fn trax_main() {
    let a = [0u32; 3];
    fill(&mut a); //~ E0596
    println!("{:?}", a);
}
