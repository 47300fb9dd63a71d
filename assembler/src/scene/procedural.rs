//! Procedural scenes: for scaling studies, a box room (five walls and a ceiling light)
//! holding a deterministic field of tessellated spheres, with about `n` triangles in total;
//! for robustness studies, a closed icosphere (every ray aimed inside its silhouette must
//! hit it, and nothing leaving its surface outwards can hit it again).

use super::{Material, PointLight, Scene, SceneError, Vec3, View};

/// Room size (the room spans `0..ROOM` on each axis, z up).
const ROOM: f32 = 10.0;
/// Triangles in the room itself: five walls (2 each) and the light (2).
const ROOM_TRIANGLES: u64 = 12;

/// SplitMix64: a small deterministic generator.
pub(super) struct Rng(pub(super) u64);

impl Rng {
    pub(super) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub(super) fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Tessellation for a sphere budget of `b` triangles: (segments, rings), giving
/// `2 * segments * (rings - 1)` triangles.
fn tessellation(b: u64) -> (u64, u64) {
    let rings = (((b as f64) / 4.0).sqrt().round() as u64 + 1).max(2);
    let segs = (b / (2 * (rings - 1))).max(3);
    (segs, rings)
}

fn sphere(scene: &mut Scene, c: Vec3, r: f32, segs: u64, rings: u64, material: u32) {
    use std::f32::consts::PI;
    let point = |i: u64, j: u64| -> Vec3 {
        // j = 0 is the north pole, j = rings the south pole.
        let theta = PI * j as f32 / rings as f32;
        let phi = 2.0 * PI * (i % segs) as f32 / segs as f32;
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        [st * cp, st * sp, ct]
    };
    let emit = |scene: &mut Scene, d: [Vec3; 3]| {
        let tri = d.map(|n| [c[0] + r * n[0], c[1] + r * n[1], c[2] + r * n[2]]);
        scene.triangles.push(tri);
        scene.normals.push(d);
        scene.texcoords.push([[0.0; 2]; 3]);
        scene.material_ids.push(material);
    };
    for i in 0..segs {
        emit(scene, [point(i, 0), point(i, 1), point(i + 1, 1)]);
        for j in 1..rings - 1 {
            let (a, b) = (point(i, j), point(i + 1, j));
            let (cc, d) = (point(i, j + 1), point(i + 1, j + 1));
            emit(scene, [a, cc, d]);
            emit(scene, [a, d, b]);
        }
        emit(
            scene,
            [
                point(i, rings - 1),
                point(i, rings),
                point(i + 1, rings - 1),
            ],
        );
    }
}

fn room(scene: &mut Scene) {
    let r = ROOM;
    let quads: [([Vec3; 4], u32); 6] = [
        (
            [[0.0, 0.0, 0.0], [r, 0.0, 0.0], [r, r, 0.0], [0.0, r, 0.0]],
            0,
        ), // floor
        ([[0.0, 0.0, r], [0.0, r, r], [r, r, r], [r, 0.0, r]], 0), // ceiling
        ([[0.0, r, 0.0], [r, r, 0.0], [r, r, r], [0.0, r, r]], 0), // back
        (
            [[0.0, 0.0, 0.0], [0.0, r, 0.0], [0.0, r, r], [0.0, 0.0, r]],
            1,
        ), // left
        ([[r, 0.0, 0.0], [r, 0.0, r], [r, r, r], [r, r, 0.0]], 2), // right
        (
            [
                [0.4 * r, 0.4 * r, 0.999 * r],
                [0.4 * r, 0.6 * r, 0.999 * r],
                [0.6 * r, 0.6 * r, 0.999 * r],
                [0.6 * r, 0.4 * r, 0.999 * r],
            ],
            3,
        ), // light
    ];
    for (q, m) in quads {
        scene.push_flat([q[0], q[1], q[2]], m);
        scene.push_flat([q[0], q[2], q[3]], m);
    }
}

/// A procedural scene with about `n` triangles (exactly `12 + spheres × per-sphere`; the
/// count is reported by [`Scene::len`]). The same `n` always gives the same scene.
pub fn procedural(n: u64) -> Result<Scene, SceneError> {
    if n < ROOM_TRIANGLES + 4 {
        return Err(SceneError::Procedural {
            spec: format!("procedural:{n}"),
            message: format!("triangle count must be at least {}", ROOM_TRIANGLES + 4),
        });
    }
    if n > super::MAX_TRIANGLES {
        return Err(SceneError::TooLarge {
            scene: format!("procedural:{n}"),
            what: "triangles",
            bytes: n * super::TRIANGLE_BYTES,
        });
    }
    let r = ROOM;
    let view = View {
        eye: [0.5 * r, -r, 0.5 * r],
        gaze: [0.0, 1.0, 0.0],
        up: [0.0, 0.0, 1.0],
        aperture: 0.0,
        left: -1.0,
        right: 1.0,
        bottom: -1.0,
        top: 1.0,
        distance: 2.0,
    };
    let mut s = Scene::new(format!("procedural:{n}"), view);
    let mat = |name: &str, d: Vec3, e: Vec3| Material {
        name: name.into(),
        diffuse: d,
        specular: [0.0; 3],
        emission: e,
        shininess: 0.0,
        illum: 1,
    };
    s.materials = vec![
        mat("white", [0.73; 3], [0.0; 3]),
        mat("red", [0.65, 0.05, 0.05], [0.0; 3]),
        mat("green", [0.12, 0.45, 0.15], [0.0; 3]),
        mat("light", [0.78; 3], [15.0; 3]),
        mat("blue", [0.1, 0.2, 0.7], [0.0; 3]),
        Material {
            specular: [0.9; 3],
            shininess: 64.0,
            illum: 2,
            ..mat("gloss", [0.2; 3], [0.0; 3])
        },
    ];
    room(&mut s);
    let budget = n - ROOM_TRIANGLES;
    // About 1000 triangles per sphere once the scene is large enough.
    let count = (budget / 1000).max(1);
    let (segs, rings) = tessellation(budget / count);
    let per = 2 * segs * (rings - 1);
    let count = (budget / per).max(1);
    s.triangles.reserve((count * per) as usize);
    s.normals.reserve((count * per) as usize);
    s.texcoords.reserve((count * per) as usize);
    s.material_ids.reserve((count * per) as usize);
    let mut rng = Rng(0x5EED_0000 ^ n);
    // Radii shrink with the sphere count so the field fills the room without swamping it.
    let rmax = 0.25 * r / (count as f32).cbrt().max(1.0);
    for k in 0..count {
        let radius = rmax * (0.3 + 0.7 * rng.unit());
        let c = [
            radius + (r - 2.0 * radius) * rng.unit(),
            radius + (r - 2.0 * radius) * rng.unit(),
            radius + (0.9 * r - 2.0 * radius) * rng.unit(),
        ];
        let m = [0, 1, 2, 4, 5][(k % 5) as usize];
        sphere(&mut s, c, radius, segs, rings, m);
    }
    s.point_lights = vec![PointLight {
        position: [0.5 * r, 0.5 * r, 0.95 * r],
        color: [1.0; 3],
    }];
    s.validate()?;
    Ok(s)
}

/// Largest icosphere subdivision count: 21 M triangles (the next, 84 M, would need over
/// 3 GB of simulated memory for the triangles alone).
pub const MAX_ICOSPHERE_SUBDIVISIONS: u64 = 10;

/// A closed icosphere: the regular icosahedron inscribed in the unit sphere centred at the
/// origin, each triangle split `subdivisions` times into four with the new vertices pushed
/// out to the sphere (`20 × 4^subdivisions` triangles). Vertices are computed once in f64
/// and shared bit for bit by every triangle that uses them, and faces wind
/// counter-clockwise seen from outside, so the mesh is watertight and consistently
/// oriented. One white material (diffuse 0.73), per-vertex normals along the radius, a
/// camera about 3.4 radii away and one point light.
pub fn icosphere(subdivisions: u64) -> Result<Scene, SceneError> {
    let spec = format!("icosphere:{subdivisions}");
    if subdivisions > MAX_ICOSPHERE_SUBDIVISIONS {
        return Err(SceneError::Procedural {
            spec,
            message: format!(
                "at most {MAX_ICOSPHERE_SUBDIVISIONS} subdivisions (20 × 4^N triangles)"
            ),
        });
    }
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut verts: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .map(unit)
    .to_vec();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, verts: &mut Vec<[f64; 3]>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (verts[a as usize], verts[b as usize]);
                verts.push(unit([0, 1, 2].map(|i| p[i] + q[i])));
                verts.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for &[a, b, c] in &faces {
            let ab = midpoint(a, b, &mut verts);
            let bc = midpoint(b, c, &mut verts);
            let ca = midpoint(c, a, &mut verts);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let verts32: Vec<Vec3> = verts.iter().map(|v| v.map(|c| c as f32)).collect();
    let view = View {
        eye: [0.6, -3.2, 0.9],
        gaze: [-0.6, 3.2, -0.9],
        up: [0.0, 0.0, 1.0],
        aperture: 0.0,
        left: -1.0,
        right: 1.0,
        bottom: -1.0,
        top: 1.0,
        distance: 2.0,
    };
    let mut s = Scene::new(spec, view);
    s.materials = vec![Material {
        name: "white".into(),
        diffuse: [0.73; 3],
        specular: [0.0; 3],
        emission: [0.0; 3],
        shininess: 0.0,
        illum: 1,
    }];
    for f in &faces {
        let tri = f.map(|i| verts32[i as usize]);
        s.triangles.push(tri);
        s.normals.push(tri);
        s.texcoords.push([[0.0; 2]; 3]);
        s.material_ids.push(0);
    }
    s.point_lights = vec![PointLight {
        position: [-3.0, -4.0, 5.0],
        color: [1.0; 3],
    }];
    s.validate()?;
    Ok(s)
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_is_closed_outward_and_on_the_unit_sphere() {
        for n in 0..4 {
            let s = icosphere(n).unwrap();
            assert_eq!(s.len() as u64, 20 * 4u64.pow(n as u32));
            // Every directed edge appears once and its reverse once: closed and
            // consistently oriented.
            let mut edges = std::collections::HashMap::new();
            for t in &s.triangles {
                for k in 0..3 {
                    let key = (t[k].map(f32::to_bits), t[(k + 1) % 3].map(f32::to_bits));
                    *edges.entry(key).or_insert(0) += 1;
                }
            }
            for (&(a, b), &c) in &edges {
                assert_eq!(c, 1, "directed edge used {c} times");
                assert_eq!(edges.get(&(b, a)), Some(&1), "edge without a twin");
            }
            for t in &s.triangles {
                let n = crate::scene::geometric_normal(t);
                let c: Vec<f32> = (0..3).map(|i| t[0][i] + t[1][i] + t[2][i]).collect();
                assert!(n[0] * c[0] + n[1] * c[1] + n[2] * c[2] > 0.0, "inward face");
                for v in t {
                    let r = (v.iter().map(|&x| (x as f64).powi(2)).sum::<f64>()).sqrt();
                    assert!((r - 1.0).abs() < 1e-6, "vertex off the sphere: {r}");
                }
            }
        }
        assert!(icosphere(MAX_ICOSPHERE_SUBDIVISIONS + 1).is_err());
    }

    #[test]
    fn sphere_triangle_count_matches_formula() {
        for (segs, rings) in [(3, 2), (8, 3), (31, 17)] {
            let mut s = Scene::new(
                "t",
                View::framing(&crate::scene::Bounds {
                    min: [0.0; 3],
                    max: [1.0; 3],
                }),
            );
            sphere(&mut s, [0.0; 3], 1.0, segs, rings, 0);
            assert_eq!(
                s.len() as u64,
                2 * segs * (rings - 1),
                "segs {segs} rings {rings}"
            );
        }
    }
}
