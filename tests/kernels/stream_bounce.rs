//! Ray streams end to end: every pixel's ray is written to a stream buffer, read back by
//! whichever TM schedules that buffer, written once more to another buffer ("a bounce"),
//! and on its second read colours its pixel. The image does not depend on which thread
//! read which ray, so `trax native` and the machine draw the same one. Thread 0 prints
//! the rays read in each stage, the sum of their pixel indices and the threads that got
//! "done" from `trax::stream::schedule`.

use trax::stream::{self, Record, RECORD_WORDS};
use trax::Vec3;

fn trax_main() {
    let w = trax::scene::width();
    let n = w * trax::scene::height();
    let nb = stream::buffers();
    let mut rec: Record = [0; RECORD_WORDS];
    let mut p = trax::global_id();
    while p < n {
        rec[0] = p;
        rec[11] = 0;
        stream::write(p * 7 % nb, &rec);
        p += trax::num_threads();
    }
    while let Some(b) = stream::schedule() {
        while stream::read(&mut rec) {
            let p = rec[0];
            if rec[11] == 0 {
                assert!(p * 7 % nb == b, "ray {} read from buffer {}", p, b);
                rec[11] = 1;
                stream::write((p * 3 + 1) % nb, &rec);
                trax::atomic_inc(1);
            } else {
                assert!((p * 3 + 1) % nb == b, "bounced ray {} read from buffer {}", p, b);
                let (x, y) = (p % w, p / w);
                let c = Vec3::new((x % 7) as f32 / 7.0, (y % 5) as f32 / 5.0, (p % 3) as f32 / 3.0);
                trax::set_pixel(x, y, c);
                trax::atomic_inc(2);
                trax::atomic_add(3, p);
            }
        }
    }
    trax::atomic_inc(4);
    trax::barrier(5);
    if trax::global_id() == 0 {
        println!(
            "{} {} {} {} {}",
            trax::global_read(1),
            trax::global_read(2),
            trax::global_read(3),
            trax::global_read(4),
            stream::capacity()
        );
    }
}
