/* The C twin of stream_bounce.rs, through trax.h's trax_stream_* API. */
#include <trax.h>

void trax_main(void) {
    unsigned int w = trax_scene_width(), n = w * trax_scene_height();
    unsigned int nb = trax_stream_buffers();
    trax_stream_record_t rec = {0};
    for (unsigned int p = trax_global_id(); p < n; p += trax_num_threads()) {
        rec[0] = p;
        rec[11] = 0;
        trax_stream_write(p * 7 % nb, rec);
    }
    unsigned int b;
    while ((b = trax_stream_schedule()) != TRAX_STREAM_DONE) {
        while (trax_stream_read(rec)) {
            unsigned int p = rec[0];
            if (rec[11] == 0) {
                if (p * 7 % nb != b) trax_panic("ray read from the wrong buffer");
                rec[11] = 1;
                trax_stream_write((p * 3 + 1) % nb, rec);
                trax_atomic_inc(1);
            } else {
                if ((p * 3 + 1) % nb != b) trax_panic("bounced ray read from the wrong buffer");
                unsigned int x = p % w, y = p / w;
                trax_set_pixel(x, y, (float)(x % 7) / 7.0f, (float)(y % 5) / 5.0f, (float)(p % 3) / 3.0f);
                trax_atomic_inc(2);
                trax_atomic_add(3, p);
            }
        }
    }
    trax_atomic_inc(4);
    trax_barrier(5);
    if (trax_global_id() == 0) {
        for (unsigned int i = 1; i <= 4; i++) {
            trax_print_uint(trax_global_read(i));
            trax_print_char(' ');
        }
        trax_print_uint(trax_stream_capacity());
        trax_print_char('\n');
    }
}
