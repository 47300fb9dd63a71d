/* The Mandelbrot set, one pixel per trax_atomic_inc, scalar float, at most 100
 * iterations. The C twin of examples/mandelbrot.rs: both draw the same image. */
#include <trax.h>

#define MAX_ITER 100u

/* Colour of a point that escaped after n iterations (black inside the set). */
static void palette(unsigned int n, float rgb[3]) {
    if (n >= MAX_ITER) {
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
        return;
    }
    float t = (float)n / (float)MAX_ITER;
    rgb[0] = trax_sqrt(t);
    rgb[1] = t;
    rgb[2] = 0.5f + 0.5f * t;
}

void trax_main(void) {
    unsigned int w = trax_scene_width();
    unsigned int h = trax_scene_height();
    unsigned int n = w * h;
    float sx = 3.0f * trax_scene_inv_width();
    float sy = 2.5f * trax_scene_inv_height();
    /* Pixels come from global register 0 (sampled simulation follows it). */
    trax_declare_work(0, n);
    for (;;) {
        unsigned int i = trax_atomic_inc(0);
        if (i >= n)
            break;
        unsigned int x = i % w;
        unsigned int y = i / w;
        float cx = -2.25f + ((float)x + 0.5f) * sx;
        float cy = 1.25f - ((float)y + 0.5f) * sy;
        float zx = 0.0f, zy = 0.0f;
        unsigned int iter = 0;
        while (iter < MAX_ITER) {
            float zx2 = zx * zx;
            float zy2 = zy * zy;
            if (zx2 + zy2 > 4.0f)
                break;
            float nzx = zx2 - zy2 + cx;
            zy = (zx + zx) * zy + cy;
            zx = nzx;
            iter++;
        }
        float rgb[3];
        palette(iter, rgb);
        trax_set_pixel(x, y, rgb[0], rgb[1], rgb[2]);
    }
}
