// A 4-million-element local array (once built as one aggregate: 10^6 elements took 32 s
// and 1.3 GB, 4*10^6 crashed the compiler).
fn trax_main() {
    let mut a = [0u32; 4000000];
    let i = trax::global_id() as usize;
    a[i] = 7;
    println!("{}", a[i]);
}
