//! Writes triangle `i`'s first vertex to pixel `i` (and zeros past the last triangle),
//! reading the triangles without the BVH: the image shows the order in which the scene's
//! triangles were laid out.

fn trax_main() {
    let n = trax::scene::width() * trax::scene::height();
    let count = trax::scene::triangle_count();
    loop {
        let i = trax::atomic_inc(0);
        if i >= n {
            break;
        }
        let c = if i < count {
            trax::scene::triangle(i).v0
        } else {
            trax::Vec3::zero()
        };
        trax::scene::set_pixel_index(i, c);
    }
}
