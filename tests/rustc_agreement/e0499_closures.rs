// Two closures that both mutate one variable, both alive.
fn trax_main() {
    let mut count = 0u32;
    let mut inc = || count += 1;
    let mut dec = || count -= 1; //~ E0499
    inc();
    dec();
    println!("{}", count);
}
