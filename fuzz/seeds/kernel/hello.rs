//! Every hardware thread says hello, in thread order: global register 1 is a ticket that
//! lets thread `k` print once threads `0..k` have printed.

fn trax_main() {
    let id = trax::global_id();
    let n = trax::num_threads();
    while trax::global_read(1) != id {}
    println!(
        "hello from thread {} of {} (TM {}, thread {})",
        id,
        n,
        trax::tm_id(),
        trax::thread_id()
    );
    let x = id as f32 * 0.5 + 0.25;
    let even = id % 2 == 0;
    let neg = -(id as i32);
    println!(
        "  x = {}, x * x = {}, even = {}, neg = {}",
        x,
        x * x,
        even,
        neg
    );
    trax::atomic_inc(1);
}
