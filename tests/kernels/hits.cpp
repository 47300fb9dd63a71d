// hits.rs through trax.hpp: the same rays, the same lines (tests/cpp_kernels.rs compares
// them bit for bit, on the machine and natively).
#include <trax.hpp>

using trax::Camera;
using trax::Ray;
using trax::Vec3;

static const unsigned int RAYS = 2048;

static void u(unsigned int x) {
    trax_print_char(' ');
    trax_print_uint(x);
}
static void f(float x) { u(trax::f32_bits(x)); }
static void v3(Vec3 v) {
    f(v.x);
    f(v.y);
    f(v.z);
}
static void s(const char *t) { trax_print_str(t); }

struct Extra {
    bool shadow = false;
    bool miss = false;
    trax::sampling::EmitterGeometry eg{};
};

static void record(unsigned int r, const Ray &ray, float t_max, const Extra &extra) {
    trax::Hit hit = trax::bvh::intersect(ray, 0.0f, t_max);
    bool any = trax::bvh::occluded(ray, 0.0f, t_max);
    bool before = trax::bvh::occluded(ray, 0.0f, hit.t);
    trax_print_uint(r);
    s(" ray");
    v3(ray.origin);
    v3(ray.dir);
    s(" tmax");
    f(t_max);
    s(" hit");
    u(hit.tri);
    f(hit.t);
    f(hit.u);
    f(hit.v);
    s(" any");
    u(any);
    u(before);
    if (hit.is_hit()) {
        trax::SurfacePoint sp(ray, hit, trax::scene::triangle(hit.tri));
        s(" p");
        v3(sp.p);
        s(" n");
        v3(sp.n);
        s(" o");
        f(sp.offset);
    }
    if (extra.miss)
        s(" miss");
    if (extra.shadow) {
        s(" eg");
        v3(extra.eg.dir);
        f(extra.eg.dist);
        f(extra.eg.dist2);
        f(extra.eg.area);
        v3(extra.eg.normal);
    }
    trax_print_char('\n');
}

extern "C" void trax_main() {
    Camera cam = Camera::load();
    float w = (float)trax::scene::width(), h = (float)trax::scene::height();
    trax::BvhNode root = trax::scene::bvh_node(0);
    unsigned int n = trax::scene::triangle_count();
    for (;;) {
        unsigned int r = trax_atomic_inc(0);
        if (r >= RAYS)
            break;
        trax::seed_pixel(r, 7);
        float px = trax::rand() * w;
        float py = trax::rand() * h;
        Ray camera_ray = cam.ray(px, py);
        switch (r % 4) {
        case 0:
            record(r, camera_ray, trax::INFINITY_F, Extra{});
            break;
        case 1: {
            float fx = trax::rand();
            float fy = trax::rand();
            float fz = trax::rand();
            Vec3 o = root.min + (root.max - root.min) * Vec3(fx, fy, fz);
            Vec3 d = trax::sampling::unit_sphere();
            record(r, Ray{o, d}, trax::INFINITY_F, Extra{});
            break;
        }
        default: {
            trax::Hit hit = trax::bvh::intersect(camera_ray, 0.0f, trax::INFINITY_F);
            if (!hit.is_hit()) {
                Extra e;
                e.miss = true;
                record(r, camera_ray, trax::INFINITY_F, e);
                continue;
            }
            trax::SurfacePoint sp(camera_ray, hit, trax::scene::triangle(hit.tri));
            Vec3 origin = sp.origin();
            if (r % 4 == 2) {
                Vec3 d = trax::sampling::cosine_hemisphere(sp.n);
                record(r, Ray{origin, d}, trax::INFINITY_F, Extra{});
            } else {
                unsigned int j = (unsigned int)(trax::rand() * (float)n);
                if (j > n - 1)
                    j = n - 1;
                trax::Triangle tri = trax::scene::triangle(j);
                Vec3 q = trax::sampling::triangle_point(tri);
                Extra e;
                e.shadow = true;
                e.eg = trax::sampling::emitter_geometry(tri, origin, q);
                record(r, Ray{origin, e.eg.dir}, e.eg.dist * (1.0f - 1e-4f), e);
            }
        }
        }
    }
}
