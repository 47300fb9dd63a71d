//! Scene transformers used in scene specs: `box:SCENE` encloses any scene in a closed box
//! (the thesis's "Dragon Box" and "Buddha Box", ch. 5: scanned models "enclosed in a box,
//! allowing rays to bounce around the environment"), and `subdivide:N:SCENE` splits every
//! triangle into four, `N` times, to reach thesis-scale triangle counts with the same shape.

use std::collections::HashMap;

use super::{normalize_or_zero, Material, Scene, SceneError, Vec3, MAX_TRIANGLES};

/// Triangles of the enclosing box: six faces of two triangles.
pub const BOX_TRIANGLES: usize = 12;

/// Name of the material appended for the box's walls.
pub const BOX_MATERIAL: &str = "box_walls";

/// Encloses `scene` in a closed axis-aligned box facing inwards: the box holds the scene's
/// triangles, the camera eye and the point lights, with a margin of 5% of its largest side
/// on every side (so the camera looks at the scene from inside the box and the lights stay
/// inside). Adds exactly [`BOX_TRIANGLES`] triangles sharing 8 corner vertices bit for
/// bit (watertight), a grey diffuse wall material, and keeps the camera and lights.
pub fn enclose_in_box(mut scene: Scene, spec: &str) -> Result<Scene, SceneError> {
    let b = scene.bounds();
    let (mut lo, mut hi) = (b.min.map(f64::from), b.max.map(f64::from));
    let points =
        std::iter::once(scene.view.eye).chain(scene.point_lights.iter().map(|l| l.position));
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i] as f64);
            hi[i] = hi[i].max(p[i] as f64);
        }
    }
    let side = (0..3).map(|i| hi[i] - lo[i]).fold(0.0f64, f64::max);
    let margin = if side > 0.0 { 0.05 * side } else { 1.0 };
    let corner = |x: usize, y: usize, z: usize| -> Vec3 {
        let pick = |i: usize, hi_side: usize| {
            let v = if hi_side == 1 {
                hi[i] + margin
            } else {
                lo[i] - margin
            };
            v as f32
        };
        [pick(0, x), pick(1, y), pick(2, z)]
    };
    if (0..3).any(|i| !corner(1, 1, 1)[i].is_finite() || !corner(0, 0, 0)[i].is_finite()) {
        return Err(SceneError::Procedural {
            spec: spec.into(),
            message: "the box around the scene does not fit in f32 coordinates".into(),
        });
    }
    let material = scene.materials.len() as u32;
    scene.materials.push(Material {
        name: BOX_MATERIAL.into(),
        diffuse: [0.73; 3],
        specular: [0.0; 3],
        emission: [0.0; 3],
        shininess: 0.0,
        illum: 1,
    });
    // Each face as four corners counter-clockwise seen from inside the box.
    let c = corner;
    let faces: [[Vec3; 4]; 6] = [
        [c(0, 0, 0), c(1, 0, 0), c(1, 1, 0), c(0, 1, 0)], // z min, seen from +z
        [c(0, 0, 1), c(0, 1, 1), c(1, 1, 1), c(1, 0, 1)], // z max, seen from -z
        [c(0, 0, 0), c(0, 0, 1), c(1, 0, 1), c(1, 0, 0)], // y min
        [c(0, 1, 0), c(1, 1, 0), c(1, 1, 1), c(0, 1, 1)], // y max
        [c(0, 0, 0), c(0, 1, 0), c(0, 1, 1), c(0, 0, 1)], // x min
        [c(1, 0, 0), c(1, 0, 1), c(1, 1, 1), c(1, 1, 0)], // x max
    ];
    for q in faces {
        scene.push_flat([q[0], q[1], q[2]], material);
        scene.push_flat([q[0], q[2], q[3]], material);
    }
    scene.name = spec.to_string();
    Ok(scene)
}

/// Largest subdivision level accepted before the triangle count is checked (4^16 × one
/// triangle already exceeds [`MAX_TRIANGLES`]).
const MAX_LEVELS: u32 = 16;

/// Splits every triangle into four at its edge midpoints, `levels` times: exactly
/// `len × 4^levels` triangles with the same surface (flat midpoint subdivision, not a
/// smoothing scheme), materials kept, normals and texture coordinates interpolated.
/// A midpoint is computed from the two endpoints' bits alone, so triangles that shared an
/// edge share its midpoint bit for bit: a watertight mesh stays watertight.
/// At most `limit` triangles (see [`super::LoadOptions::triangle_limit`]): more are refused
/// before any is split.
pub fn subdivide(
    mut scene: Scene,
    levels: u32,
    spec: &str,
    limit: u64,
) -> Result<Scene, SceneError> {
    let too_many = |n: Option<u64>| SceneError::Procedural {
        spec: spec.into(),
        message: format!(
            "{} triangles × 4^{levels} = {} triangles, more than the {limit} that fit in memory \
             with the scene data the kernel reads",
            scene.len(),
            n.map_or("over 2^64".to_string(), |n| n.to_string())
        ),
    };
    let total = (levels <= MAX_LEVELS)
        .then(|| (scene.len() as u64).checked_mul(1u64 << (2 * levels)))
        .flatten();
    match total {
        Some(n) if n <= limit.min(MAX_TRIANGLES) => {}
        n => return Err(too_many(n)),
    }
    for _ in 0..levels {
        let n = scene.len() * 4;
        let mut tris = Vec::with_capacity(n);
        let mut normals = Vec::with_capacity(n);
        let mut uvs = Vec::with_capacity(n);
        let mut mats = Vec::with_capacity(n);
        // Midpoints by unordered endpoint pair, so both triangles of an edge agree.
        let mut cache: HashMap<([u32; 3], [u32; 3]), Vec3> = HashMap::new();
        for k in 0..scene.len() {
            let t = scene.triangles[k];
            let (nn, uv) = (scene.normals[k], scene.texcoords[k]);
            let mut mid = |a: Vec3, b: Vec3| -> Vec3 {
                let (ka, kb) = (a.map(f32::to_bits), b.map(f32::to_bits));
                let key = if ka <= kb { (ka, kb) } else { (kb, ka) };
                *cache.entry(key).or_insert_with(|| {
                    [0, 1, 2].map(|i| ((a[i] as f64 + b[i] as f64) * 0.5) as f32)
                })
            };
            let p = [mid(t[0], t[1]), mid(t[1], t[2]), mid(t[2], t[0])];
            let nm = |a: Vec3, b: Vec3| normalize_or_zero([0, 1, 2].map(|i| a[i] + b[i]));
            let n3 = [nm(nn[0], nn[1]), nm(nn[1], nn[2]), nm(nn[2], nn[0])];
            let um = |a: [f32; 2], b: [f32; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            let u3 = [um(uv[0], uv[1]), um(uv[1], uv[2]), um(uv[2], uv[0])];
            // Corners first, then the middle triangle; all wound as the parent.
            for (v, n, u) in [
                (
                    [t[0], p[0], p[2]],
                    [nn[0], n3[0], n3[2]],
                    [uv[0], u3[0], u3[2]],
                ),
                (
                    [p[0], t[1], p[1]],
                    [n3[0], nn[1], n3[1]],
                    [u3[0], uv[1], u3[1]],
                ),
                (
                    [p[2], p[1], t[2]],
                    [n3[2], n3[1], nn[2]],
                    [u3[2], u3[1], uv[2]],
                ),
                (
                    [p[0], p[1], p[2]],
                    [n3[0], n3[1], n3[2]],
                    [u3[0], u3[1], u3[2]],
                ),
            ] {
                tris.push(v);
                normals.push(n);
                uvs.push(u);
                mats.push(scene.material_ids[k]);
            }
        }
        scene.triangles = tris;
        scene.normals = normals;
        scene.texcoords = uvs;
        scene.material_ids = mats;
    }
    scene.name = spec.to_string();
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{cornell_box, geometric_normal, icosphere, load_scene, LoadOptions};

    /// Every directed edge once and its reverse once: closed and consistently oriented.
    fn closed(tris: &[[Vec3; 3]]) -> bool {
        let mut edges = HashMap::new();
        for t in tris {
            for k in 0..3 {
                let key = (t[k].map(f32::to_bits), t[(k + 1) % 3].map(f32::to_bits));
                *edges.entry(key).or_insert(0) += 1;
            }
        }
        edges
            .iter()
            .all(|(&(a, b), &c)| c == 1 && edges.get(&(b, a)) == Some(&1))
    }

    fn area(t: &[Vec3; 3]) -> f64 {
        let c = crate::scene::cross(crate::scene::sub(t[1], t[0]), crate::scene::sub(t[2], t[0]));
        0.5 * c.iter().map(|&x| (x as f64).powi(2)).sum::<f64>().sqrt()
    }

    #[test]
    fn box_adds_twelve_closed_inward_triangles_around_everything() {
        let inner = cornell_box();
        let (n, eye, lights) = (inner.len(), inner.view.eye, inner.point_lights.clone());
        let s = enclose_in_box(inner, "box:cornell").unwrap();
        assert_eq!(s.len(), n + BOX_TRIANGLES);
        let walls = &s.triangles[n..];
        assert!(closed(walls));
        let b = crate::scene::Bounds {
            min: walls
                .iter()
                .flatten()
                .fold([f32::MAX; 3], |m, v| [0, 1, 2].map(|i| m[i].min(v[i]))),
            max: walls
                .iter()
                .flatten()
                .fold([f32::MIN; 3], |m, v| [0, 1, 2].map(|i| m[i].max(v[i]))),
        };
        let c = b.center();
        for t in walls {
            // Facing inwards: the normal points from the wall towards the centre.
            let nrm = geometric_normal(t);
            let to_c = crate::scene::sub(c, t[0]);
            assert!(
                (0..3).map(|i| nrm[i] * to_c[i]).sum::<f32>() > 0.0,
                "outward wall"
            );
        }
        let inside = |p: Vec3| (0..3).all(|i| b.min[i] < p[i] && p[i] < b.max[i]);
        assert!(inside(eye));
        assert!(lights.iter().all(|l| inside(l.position)));
        assert!(s.triangles[..n].iter().flatten().all(|&v| inside(v)));
        let m = &s.materials[s.material_ids[n] as usize];
        assert_eq!(m.name, BOX_MATERIAL);
    }

    #[test]
    fn subdivision_multiplies_by_four_keeps_area_and_closedness() {
        for levels in 0..3u32 {
            let base = icosphere(1).unwrap();
            let a0: f64 = base.triangles.iter().map(area).sum();
            let s = subdivide(base, levels, "t", MAX_TRIANGLES).unwrap();
            assert_eq!(s.len(), 80 * 4usize.pow(levels));
            assert!(closed(&s.triangles), "level {levels}: not watertight");
            let a1: f64 = s.triangles.iter().map(area).sum();
            assert!((a1 - a0).abs() < 1e-5 * a0, "area {a0} -> {a1}");
            assert!(s
                .normals
                .iter()
                .flatten()
                .all(|n| { ((n.iter().map(|&x| x * x).sum::<f32>()) - 1.0).abs() < 1e-5 }));
        }
        let e = subdivide(cornell_box(), 11, "subdivide:11:cornell", MAX_TRIANGLES).unwrap_err();
        assert!(e.to_string().contains("subdivide:11:cornell"), "{e}");
        assert!(subdivide(cornell_box(), u32::MAX, "x", MAX_TRIANGLES).is_err());
    }

    #[test]
    fn split_spec_finds_the_innermost_file() {
        use crate::scene::split_spec;
        assert_eq!(
            split_spec("box:subdivide:2:d/dragon.obj"),
            ("box:subdivide:2:", "d/dragon.obj", true)
        );
        assert_eq!(
            split_spec("box:hairball:9:1"),
            ("box:", "hairball:9:1", false)
        );
        assert_eq!(split_spec("cornell"), ("", "cornell", false));
        assert_eq!(split_spec("x.obj"), ("", "x.obj", true));
        assert!(!split_spec("subdivide:1:icosphere:2").2);
    }

    #[test]
    fn specs_nest_and_bad_parts_are_named() {
        let o = LoadOptions::default();
        let s = load_scene("box:subdivide:2:icosphere:1", &o).unwrap();
        assert_eq!(s.len(), 80 * 16 + 12);
        assert!(closed(&s.triangles));
        assert_eq!(load_scene("hairball:500:9", &o).unwrap().len(), 500);
        assert_eq!(load_scene("vegetation:77", &o).unwrap().len(), 77);
        for (spec, part) in [
            ("subdivide:x:cornell", "`x` is not a subdivision count"),
            ("subdivide:2", "expected `subdivide:N:SCENE`"),
            ("box:", "expected `box:SCENE`"),
            ("box", "expected `box:SCENE`"),
            ("box:nope", "unknown scene `nope`"),
            ("hairball:lots", "`lots` is not a triangle count"),
            ("hairball:500:-1", "`-1` is not a seed"),
            ("vegetation", "expected `vegetation:N[:SEED]`"),
            ("box:box:box:box:box:box:box:box:box:cornell", "nested"),
        ] {
            let e = load_scene(spec, &o).unwrap_err().to_string();
            assert!(e.contains(part), "{spec}: {e}");
        }
    }
}
