// Path tracer in C++, written the way a C++ ray-tracing kernel usually is: an abstract
// Material with virtual Lambertian and Emissive surfaces, light sources as classes behind
// a template, operator overloading (trax::Vec3), a switch, and globals. The same estimator
// as examples/pathtracer.rs -- next-event estimation at every vertex (one uniformly chosen
// emissive triangle and every point light, with shadow rays), cosine-weighted
// continuation through sin/cos (trax_sinf/trax_cosf, the prelude's libm), `max_depth`
// bounces and `spp` jittered samples per pixel, each sample on its own random stream --
// so it renders the same picture.
#include <trax.hpp>

using trax::Hit;
using trax::Ray;
using trax::SurfacePoint;
using trax::Vec3;

// ---- Globals ----

// 2 pi and 1 / pi (f32).
constexpr float TAU = 6.28318530717958647692f;
constexpr float INV_PI = 0.318309886183790671538f;
// Shadow rays towards an emitter stop this fraction short of it, so the emitter's own
// triangle does not occlude.
constexpr float SHADOW_SHORTEN = 1e-4f;

// What every thread reads from the scene header, once (a global object with a
// constructor: it runs on every hardware thread before trax_main, from .init_array).
struct RenderSettings {
    unsigned int width, max_depth, spp;
    float inv_spp;
    RenderSettings()
        : width(trax::scene::width()), max_depth(trax::scene::max_depth()),
          spp(trax::scene::spp() > 0 ? trax::scene::spp() : 1), inv_spp(1.0f / (float)spp) {}
};
static const RenderSettings settings;

// ---- Materials ----

class Path;

// What a surface does to light.
class Material {
  public:
    // Diffuse reflectance.
    virtual Vec3 albedo() const = 0;
    // Light emitted towards the camera, seen directly.
    virtual Vec3 emitted() const { return Vec3::zero(); }
    // Light leaving the surface point towards the previous vertex: emission (first
    // vertex only) plus direct light from the sources.
    virtual Vec3 shade(const Path &path, const SurfacePoint &sp, unsigned int depth) const = 0;

  protected:
    // Light from every source reflected at `sp` (Lambertian BRDF albedo / pi).
    Vec3 direct_light(const Path &path, const SurfacePoint &sp) const;
};

// A Lambertian reflector.
class Lambertian : public Material {
  public:
    explicit Lambertian(Vec3 albedo) : albedo_(albedo) {}
    Vec3 albedo() const override { return albedo_; }
    Vec3 shade(const Path &path, const SurfacePoint &sp, unsigned int depth) const override;

  private:
    Vec3 albedo_;
};

// A light source that may also reflect.
class Emissive : public Material {
  public:
    Emissive(Vec3 emission, Vec3 albedo) : emission_(emission), albedo_(albedo) {}
    Vec3 albedo() const override { return albedo_; }
    Vec3 emitted() const override { return emission_; }
    Vec3 shade(const Path &path, const SurfacePoint &sp, unsigned int depth) const override;

  private:
    Vec3 emission_, albedo_;
};

enum class SurfaceKind { Diffuse, Emitter };

// The surface kind of a scene material.
static SurfaceKind kind_of(const trax::Material &m) {
    return m.emission.is_black() ? SurfaceKind::Diffuse : SurfaceKind::Emitter;
}

// ---- Light sources ----

// A sample of a light: direction and distance to it, and its contribution before the
// BRDF when unoccluded.
struct LightSample {
    Vec3 dir;
    float dist;
    Vec3 radiance;
    bool valid;
};

// One uniformly chosen emissive triangle (area light; pdf 1 / (emitters * area)).
class AreaLights {
  public:
    AreaLights() : count_(trax::scene::emitter_count()) {}
    unsigned int count() const { return count_ > 0 ? 1 : 0; }
    LightSample sample(unsigned int, const SurfacePoint &sp, Vec3 origin) const {
        unsigned int k = (unsigned int)(trax::rand() * (float)count_);
        if (k > count_ - 1)
            k = count_ - 1;
        unsigned int tri_index = trax::scene::emitter(k);
        trax::Triangle tri = trax::scene::triangle(tri_index);
        Vec3 q = trax::sampling::triangle_point(tri);
        // Direction, distance, area / distance^2 and the light's normal at every scale.
        trax::sampling::EmitterGeometry eg = trax::sampling::emitter_geometry(tri, origin, q);
        float cos_surf = sp.n.dot(eg.dir);
        float cos_light = __builtin_fabsf(eg.normal.dot(eg.dir));
        LightSample s{eg.dir, eg.dist * (1.0f - SHADOW_SHORTEN), Vec3::zero(), false};
        if (cos_surf > 0.0f && cos_light > 0.0f) {
            trax::Material m = trax::scene::triangle_material(tri_index);
            if (kind_of(m) == SurfaceKind::Emitter) {
                // Solid-angle conversion cos_light / d^2 over the pdf.
                float g = cos_surf * cos_light / eg.dist2 * eg.area * (float)count_;
                s.radiance = m.emission * g;
                s.valid = true;
            }
        }
        return s;
    }

  private:
    unsigned int count_;
};

// Every point light (isotropic, intensity `color`, falloff 1 / d^2).
class PointLights {
  public:
    unsigned int count() const { return trax::scene::point_light_count(); }
    LightSample sample(unsigned int k, const SurfacePoint &sp, Vec3 origin) const {
        trax::PointLight light = trax::scene::point_light(k);
        Vec3 to_light = light.position - origin;
        float dist2 = to_light.length_squared();
        // Right at every scale (`length` rescales; dist2 may overflow to a contribution
        // of 0).
        float dist = to_light.length();
        Vec3 l = to_light * (1.0f / dist);
        float cos = sp.n.dot(l);
        return LightSample{l, dist, light.color * (cos / dist2), cos > 0.0f};
    }
};

// ---- Paths ----

class Path {
  public:
    explicit Path(unsigned int max_depth) : max_depth_(max_depth) {}

    // Radiance along a camera ray.
    Vec3 radiance(Ray ray) const {
        Vec3 throughput = Vec3::splat(1.0f);
        Vec3 l;
        unsigned int depths = max_depth_ > 0 ? max_depth_ : 1;
        for (unsigned int depth = 0; depth < depths; depth++) {
            Hit hit = trax::bvh::intersect(ray, 0.0f, trax::INFINITY_F);
            if (!hit.is_hit()) {
                l += throughput * trax::scene::background();
                break;
            }
            trax::Material m = trax::scene::triangle_material(hit.tri);
            // New rays start just off the surface, by the hit point's rounding error.
            SurfacePoint sp(ray, hit, trax::scene::triangle(hit.tri));
            Vec3 albedo;
            switch (kind_of(m)) {
            case SurfaceKind::Diffuse: {
                Lambertian surface(m.diffuse);
                l += throughput * surface.shade(*this, sp, depth);
                albedo = surface.albedo();
                break;
            }
            case SurfaceKind::Emitter: {
                Emissive surface(m.emission, m.diffuse);
                l += throughput * surface.shade(*this, sp, depth);
                albedo = surface.albedo();
                break;
            }
            }
            if (depth + 1 >= max_depth_ || albedo.is_black())
                break;
            // Cosine sampling: brdf * cos / pdf = albedo.
            throughput *= albedo;
            ray = Ray{sp.origin(), cosine_sample(sp.n)};
        }
        return l;
    }

    // Direct light at `sp` from every source of kind L, with shadow rays.
    template <class L> Vec3 direct(const L &lights, const SurfacePoint &sp, Vec3 brdf) const {
        Vec3 sum;
        Vec3 origin = sp.origin();
        for (unsigned int k = 0; k < lights.count(); k++) {
            LightSample s = lights.sample(k, sp, origin);
            if (s.valid && !trax::bvh::occluded(Ray{origin, s.dir}, 0.0f, s.dist))
                sum += brdf * s.radiance;
        }
        return sum;
    }

  private:
    // A cosine-weighted direction around unit normal n (pdf cos(theta) / pi), by
    // inverting the distribution: radius sqrt(u1), angle 2 pi u2.
    static Vec3 cosine_sample(Vec3 n) {
        float r2 = trax::rand();
        float phi = TAU * trax::rand();
        float r = __builtin_sqrtf(r2);
        float s = trax_sinf(phi);
        float c = trax_cosf(phi);
        float z = __builtin_sqrtf(trax::max(1.0f - r2, 0.0f));
        return trax::sampling::Onb(n).to_world(Vec3(r * c, r * s, z));
    }

    unsigned int max_depth_;
};

Vec3 Material::direct_light(const Path &path, const SurfacePoint &sp) const {
    Vec3 brdf = albedo() * INV_PI;
    return path.direct(AreaLights(), sp, brdf) + path.direct(PointLights(), sp, brdf);
}

Vec3 Lambertian::shade(const Path &path, const SurfacePoint &sp, unsigned int) const {
    return direct_light(path, sp);
}

Vec3 Emissive::shade(const Path &path, const SurfacePoint &sp, unsigned int depth) const {
    // Emission reaches the image directly (camera rays) or through light sampling, never
    // through a continuation ray, so no light is counted twice.
    Vec3 direct = direct_light(path, sp);
    return depth == 0 ? emitted() + direct : direct;
}

extern "C" void trax_main() {
    const trax::Camera cam = trax::Camera::load();
    const Path path(settings.max_depth);
    // Pixels are handed out dynamically; each sample seeds its own random stream, so the
    // image is the same on every chip and natively.
    trax::scene::PixelShare share = trax::scene::pixel_share();
    for (unsigned int i = share.next_pixel(); i != trax::NO_PIXEL; i = share.next_pixel()) {
        Vec3 c;
        for (unsigned int s = 0; s < settings.spp; s++) {
            trax::seed_pixel(i, s);
            c += path.radiance(cam.jittered_ray(i % settings.width, i / settings.width));
        }
        trax::scene::set_pixel_index(i, c * settings.inv_spp);
    }
}
