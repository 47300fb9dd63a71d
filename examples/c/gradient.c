/* A colour gradient: red grows to the right, green grows downwards, blue is constant.
 * Threads take pixels one at a time from global register 0. The C twin of
 * examples/gradient.rs: both draw the same image. */
#include <trax.h>

void trax_main(void) {
    unsigned int w = trax_scene_width();
    unsigned int h = trax_scene_height();
    unsigned int n = w * h;
    float inv_w = trax_scene_inv_width();
    float inv_h = trax_scene_inv_height();
    /* Pixels come from global register 0 (sampled simulation follows it). */
    trax_declare_work(0, n);
    for (;;) {
        unsigned int i = trax_atomic_inc(0);
        if (i >= n)
            break;
        unsigned int x = i % w;
        unsigned int y = i / w;
        float r = ((float)x + 0.5f) * inv_w;
        float g = ((float)y + 0.5f) * inv_h;
        trax_set_pixel(x, y, r, g, 0.25f);
    }
}
