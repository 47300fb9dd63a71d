//! Stand-ins for thesis scenes that are not available here, built to have their memory
//! behaviour (thesis ch. 5, Table 5.1): `hairball:N[:seed]`, a dense ball of thin random
//! tubes whose long, crossing strands give overlapping BVH boxes and incoherent secondary
//! rays; `vegetation:N[:seed]`, a wide field of small instanced leaves seen at a grazing
//! angle, so rays pass by many tiny triangles spread over a large footprint. Both have
//! exactly `N` triangles and are a pure function of `(N, seed)`.

use super::procedural::Rng;
use super::{Material, PointLight, Scene, SceneError, Vec3, View, MAX_TRIANGLES};

/// Seed used when a spec gives none.
pub const DEFAULT_SEED: u64 = 1;

/// Sides of a hairball tube's cross-section.
const TUBE_SIDES: usize = 3;
/// Segments along one hairball strand.
const STRAND_SEGMENTS: usize = 16;
/// Triangles of one full strand.
pub const STRAND_TRIANGLES: u64 = (2 * TUBE_SIDES * STRAND_SEGMENTS) as u64;

/// Smallest scene each generator accepts (one strand; the ground and one leaf).
const MIN_HAIRBALL: u64 = STRAND_TRIANGLES;
const MIN_VEGETATION: u64 = GROUND_TRIANGLES + LEAF_TRIANGLES;

fn check_count(spec: &str, n: u64, min: u64) -> Result<(), SceneError> {
    if n < min {
        return Err(SceneError::Procedural {
            spec: spec.into(),
            message: format!("triangle count must be at least {min}"),
        });
    }
    if n > MAX_TRIANGLES {
        return Err(SceneError::TooLarge {
            scene: spec.into(),
            what: "triangles",
            bytes: n * 36,
        });
    }
    Ok(())
}

fn material(name: &str, diffuse: Vec3) -> Material {
    Material {
        name: name.into(),
        diffuse,
        specular: [0.0; 3],
        emission: [0.0; 3],
        shininess: 0.0,
        illum: 1,
    }
}

fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: Vec3, s: f32) -> Vec3 {
    a.map(|c| c * s)
}

fn norm(a: Vec3) -> Vec3 {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if l > 0.0 {
        scale(a, 1.0 / l)
    } else {
        [0.0, 0.0, 1.0]
    }
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A uniformly distributed unit vector.
fn direction(rng: &mut Rng) -> Vec3 {
    let z = 2.0 * rng.unit() - 1.0;
    let phi = std::f32::consts::TAU * rng.unit();
    let r = (1.0 - z * z).max(0.0).sqrt();
    [r * phi.cos(), r * phi.sin(), z]
}

/// Pushes a triangle with per-vertex normals, stopping once the scene holds `limit`.
fn emit(s: &mut Scene, limit: usize, tri: [Vec3; 3], normals: [Vec3; 3], m: u32) {
    if s.triangles.len() < limit {
        s.triangles.push(tri);
        s.normals.push(normals);
        s.texcoords.push([[0.0; 2]; 3]);
        s.material_ids.push(m);
    }
}

/// A dense ball of thin tubes: strands of [`STRAND_SEGMENTS`] segments with a triangular
/// cross-section (radius 0.15% to 2% of the ball's, thinner as strands are added), each a random walk that starts inside the
/// unit ball and turns back towards the centre when it leaves it; `n` triangles exactly
/// (the last strand is cut short when `n` is not a multiple of [`STRAND_TRIANGLES`]).
pub fn hairball(n: u64, seed: u64) -> Result<Scene, SceneError> {
    let spec = format!("hairball:{n}:{seed}");
    check_count(&spec, n, MIN_HAIRBALL)?;
    let view = View {
        eye: [0.0, -3.0, 0.6],
        gaze: [0.0, 3.0, -0.6],
        up: [0.0, 0.0, 1.0],
        aperture: 0.0,
        left: -1.0,
        right: 1.0,
        bottom: -1.0,
        top: 1.0,
        distance: 2.0,
    };
    let mut s = Scene::new(spec, view);
    s.materials = vec![
        material("hair_dark", [0.35, 0.25, 0.15]),
        material("hair_light", [0.75, 0.6, 0.4]),
    ];
    let limit = n as usize;
    s.triangles.reserve(limit);
    s.normals.reserve(limit);
    s.texcoords.reserve(limit);
    s.material_ids.reserve(limit);
    let mut rng = Rng(0x04A1_BA11 ^ seed.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    // Thicker tubes for fewer strands, so any size looks like a dense ball: the strands'
    // silhouettes cover the ball's disc about three times over (2 r L S ≈ 3π).
    let strands = n.div_ceil(STRAND_TRIANGLES) as f32;
    let step = 0.12f32;
    let radius = (3.0 * std::f32::consts::PI / (2.0 * step * STRAND_SEGMENTS as f32 * strands))
        .clamp(0.0015, 0.02);
    let mut strand = 0u32;
    while s.triangles.len() < limit {
        let m = strand % 2;
        strand += 1;
        // Start anywhere in the ball (rejection sampling), heading anywhere.
        let mut p = loop {
            let q = [0, 1, 2].map(|_| 2.0 * rng.unit() - 1.0);
            if q[0] * q[0] + q[1] * q[1] + q[2] * q[2] <= 1.0 {
                break q;
            }
        };
        let mut d = direction(&mut rng);
        let ring = |c: Vec3, d: Vec3| -> [(Vec3, Vec3); TUBE_SIDES] {
            let helper = if d[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            let u = norm(cross(d, helper));
            let w = cross(d, u);
            std::array::from_fn(|k| {
                let a = std::f32::consts::TAU * k as f32 / TUBE_SIDES as f32;
                let nrm = add(scale(u, a.cos()), scale(w, a.sin()));
                (add(c, scale(nrm, radius)), nrm)
            })
        };
        let mut prev = ring(p, d);
        for _ in 0..STRAND_SEGMENTS {
            // Turn a little; turn home when outside the ball.
            d = norm(add(d, scale(direction(&mut rng), 0.5)));
            let r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
            if r2 > 1.0 {
                d = norm(add(d, scale(p, -1.0)));
            }
            p = add(p, scale(d, step));
            let next = ring(p, d);
            for k in 0..TUBE_SIDES {
                let k1 = (k + 1) % TUBE_SIDES;
                let (a, b, c, e) = (prev[k], prev[k1], next[k], next[k1]);
                emit(&mut s, limit, [a.0, b.0, e.0], [a.1, b.1, e.1], m);
                emit(&mut s, limit, [a.0, e.0, c.0], [a.1, e.1, c.1], m);
            }
            prev = next;
        }
    }
    s.point_lights = vec![PointLight {
        position: [2.0, -3.0, 3.0],
        color: [1.0; 3],
    }];
    s.validate()?;
    Ok(s)
}

/// Triangles of the vegetation's ground (one quad).
const GROUND_TRIANGLES: u64 = 2;
/// Triangles of one leaf: two halves folded along the midrib.
pub const LEAF_TRIANGLES: u64 = 2;
/// Leaves on one plant.
const LEAVES_PER_PLANT: u64 = 24;

/// A field of plants on a ground quad: every leaf is the same two-triangle leaf (folded
/// along its midrib), instanced with its own position, yaw, tilt and size; plants stand
/// on a square field whose side grows with the square root of the leaf count (constant
/// density: more leaves cover more ground), seen from above one edge at a grazing angle.
/// `n` triangles exactly (an odd `n` leaves the last leaf a single half).
pub fn vegetation(n: u64, seed: u64) -> Result<Scene, SceneError> {
    let spec = format!("vegetation:{n}:{seed}");
    check_count(&spec, n, MIN_VEGETATION)?;
    let leaves = (n - GROUND_TRIANGLES).div_ceil(LEAF_TRIANGLES);
    let plants = leaves.div_ceil(LEAVES_PER_PLANT);
    // About one plant per square unit.
    let side = (plants as f32).sqrt().max(1.0) * 1.5;
    let view = View {
        eye: [0.5 * side, -0.15 * side - 2.0, 0.12 * side + 1.5],
        gaze: [0.0, 1.0, -0.3],
        up: [0.0, 0.0, 1.0],
        aperture: 0.0,
        left: -1.0,
        right: 1.0,
        bottom: -0.75,
        top: 0.75,
        distance: 1.5,
    };
    let mut s = Scene::new(spec, view);
    s.materials = vec![
        material("ground", [0.3, 0.22, 0.12]),
        material("leaf_dark", [0.08, 0.3, 0.06]),
        material("leaf_light", [0.25, 0.55, 0.12]),
        material("leaf_yellow", [0.5, 0.55, 0.1]),
    ];
    let limit = n as usize;
    s.triangles.reserve(limit);
    s.normals.reserve(limit);
    s.texcoords.reserve(limit);
    s.material_ids.reserve(limit);
    let g = [
        [0.0, 0.0, 0.0],
        [side, 0.0, 0.0],
        [side, side, 0.0],
        [0.0, side, 0.0],
    ];
    s.push_flat([g[0], g[1], g[2]], 0);
    s.push_flat([g[0], g[2], g[3]], 0);
    let mut rng = Rng(0x1EAF_5EED ^ seed.wrapping_mul(0xD134_2543_DE82_EF95));
    // The leaf in its own frame: base at the origin, tip along +x, folded up along x.
    let leaf: [Vec3; 4] = [
        [0.0, 0.0, 0.0],    // base
        [0.5, 0.18, 0.06],  // left edge
        [1.0, 0.0, 0.0],    // tip
        [0.5, -0.18, 0.06], // right edge
    ];
    let mut placed = 0u64;
    'field: for _ in 0..plants {
        let root = [side * rng.unit(), side * rng.unit(), 0.0f32];
        let height = 0.4 + 0.8 * rng.unit();
        for k in 0..LEAVES_PER_PLANT {
            if placed == leaves {
                break 'field;
            }
            placed += 1;
            let yaw = std::f32::consts::TAU * rng.unit();
            let tilt = 0.9 * rng.unit() - 0.2; // radians above the horizontal
            let size = 0.15 + 0.2 * rng.unit();
            let z = height * (k as f32 + rng.unit()) / LEAVES_PER_PLANT as f32;
            let (sy, cy) = yaw.sin_cos();
            let (st, ct) = tilt.sin_cos();
            // Leaf frame -> world: tilt about y, then yaw about z, then scale and move.
            let place = |v: Vec3| -> Vec3 {
                let (x, y, zz) = (v[0] * ct - v[2] * st, v[1], v[0] * st + v[2] * ct);
                [
                    root[0] + size * (x * cy - y * sy),
                    root[1] + size * (x * sy + y * cy),
                    root[2] + z + size * zz,
                ]
            };
            let w = leaf.map(place);
            let m = 1 + (rng.next_u64() % 3) as u32;
            for tri in [[w[0], w[2], w[1]], [w[0], w[3], w[2]]] {
                if s.triangles.len() < limit {
                    s.push_flat(tri, m);
                }
            }
        }
    }
    s.point_lights = vec![PointLight {
        position: [0.3 * side, -0.2 * side, 2.0 * side.max(2.0)],
        color: [1.0; 3],
    }];
    s.validate()?;
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bits(s: &Scene) -> Vec<u32> {
        let mut v: Vec<u32> = s
            .triangles
            .iter()
            .flatten()
            .flatten()
            .map(|c| c.to_bits())
            .collect();
        v.extend(s.normals.iter().flatten().flatten().map(|c| c.to_bits()));
        v.extend(&s.material_ids);
        v
    }

    #[test]
    fn counts_are_exact_for_any_n() {
        for n in [96, 97, 191, 192, 1000, 4321] {
            assert_eq!(hairball(n, 1).unwrap().len() as u64, n, "hairball:{n}");
        }
        for n in [4, 5, 6, 1001, 4321] {
            assert_eq!(vegetation(n, 1).unwrap().len() as u64, n, "vegetation:{n}");
        }
        assert!(hairball(95, 1).is_err());
        assert!(vegetation(3, 1).is_err());
        assert!(hairball(MAX_TRIANGLES + 1, 1).is_err());
        assert!(vegetation(MAX_TRIANGLES + 1, 1).is_err());
    }

    #[test]
    fn same_seed_same_bits_other_seed_other_scene() {
        for make in [hairball, vegetation] {
            let (a, b, c) = (
                make(3000, 7).unwrap(),
                make(3000, 7).unwrap(),
                make(3000, 8).unwrap(),
            );
            assert_eq!(bits(&a), bits(&b));
            assert_ne!(bits(&a), bits(&c));
        }
    }

    /// The hairball stays a ball: strands turn home within a step or two of leaving it.
    #[test]
    fn hairball_is_a_ball_of_thin_tubes() {
        let s = hairball(20_000, 3).unwrap();
        let r = s
            .triangles
            .iter()
            .flatten()
            .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
            .fold(0.0f32, f32::max);
        assert!(r < 1.0 + 3.0 * 0.12 + 0.02, "radius {r}");
        // Tube triangles are long and thin: edges at most a step plus a diameter.
        for t in &s.triangles {
            for k in 0..3 {
                let d = crate::scene::sub(t[k], t[(k + 1) % 3]);
                assert!((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() < 0.12 + 0.05);
            }
        }
    }

    /// Every leaf is the same leaf: both halves of a leaf have the same shape (area ratio
    /// and edge lengths scale together) and leaves lie above the ground, inside the field.
    #[test]
    fn vegetation_leaves_are_instances_above_the_field() {
        let s = vegetation(2 + 2 * 500, 5).unwrap();
        let b = s.bounds();
        let side = b.max[0].max(b.max[1]);
        let area = |t: &[Vec3; 3]| {
            let c =
                crate::scene::cross(crate::scene::sub(t[1], t[0]), crate::scene::sub(t[2], t[0]));
            0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
        };
        let mut ratios = Vec::new();
        for leaf in s.triangles[2..].chunks(2) {
            for t in leaf {
                for v in t {
                    assert!(v[2] >= -0.4 && v[2] < 1.6, "{v:?}");
                    assert!(v[0] > -0.5 && v[0] < side + 0.5);
                }
            }
            // A leaf's area over its midrib length squared is the same for every leaf.
            let rib = crate::scene::sub(leaf[0][1], leaf[0][0]);
            let len2 = rib[0] * rib[0] + rib[1] * rib[1] + rib[2] * rib[2];
            ratios.push((area(&leaf[0]) + area(&leaf[1])) / len2);
        }
        let (lo, hi) = ratios
            .iter()
            .fold((f32::MAX, 0.0f32), |(l, h), &r| (l.min(r), h.max(r)));
        assert!(hi - lo < 1e-3 * hi, "leaf shapes differ: {lo} .. {hi}");
    }
}
