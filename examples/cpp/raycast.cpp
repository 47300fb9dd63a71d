// Ray caster in C++: one primary ray per pixel through the BVH, Lambertian shading by every
// point light with a hard shadow ray each, plus a small ambient term and emission. The C++
// twin of examples/raycast.rs, on trax.hpp (the prelude's camera, BVH traversal and
// surface points): both draw the same image, bit for bit.
#include <trax.hpp>

using trax::Ray;
using trax::Vec3;

// Ambient fraction of the diffuse colour.
constexpr float AMBIENT = 0.1f;

// Colour seen along `ray`.
static Vec3 trace(const Ray &ray) {
    trax::Hit hit = trax::bvh::intersect(ray, 0.0f, trax::INFINITY_F);
    if (!hit.is_hit())
        return trax::scene::background();
    trax::Material mat = trax::scene::triangle_material(hit.tri);
    // Hit point and geometric normal facing the viewer; shadow rays start just off the
    // surface, by the hit point's rounding error.
    trax::SurfacePoint sp(ray, hit, trax::scene::triangle(hit.tri));
    Vec3 origin = sp.origin();
    Vec3 c = mat.emission + mat.diffuse * AMBIENT;
    unsigned int lights = trax::scene::point_light_count();
    for (unsigned int k = 0; k < lights; k++) {
        trax::PointLight light = trax::scene::point_light(k);
        Vec3 to_light = light.position - origin;
        float dist = to_light.length();
        Vec3 l = to_light * (1.0f / dist);
        float cos = sp.n.dot(l);
        if (cos > 0.0f && !trax::bvh::occluded(Ray{origin, l}, 0.0f, dist))
            c += mat.diffuse * (light.color * cos);
    }
    return c;
}

extern "C" void trax_main() {
    const trax::Camera cam = trax::Camera::load();
    unsigned int w = trax::scene::width();
    unsigned int n = w * trax::scene::height();
    // Pixels come from global register 0 (sampled simulation follows it).
    trax_declare_work(0, n);
    for (;;) {
        unsigned int i = trax_atomic_inc(0);
        if (i >= n)
            break;
        trax::scene::set_pixel_index(i, trace(cam.pixel_ray(i % w, i / w)));
    }
}
