//! The embedded default scene: the Cornell box from Cornell's published measurements
//! (floor about 556 × 559 mm, ceiling at 548.8 mm, a 130 × 105 mm light, a short and a tall
//! block), authored here as quads.
//!
//! The published data is y-up with the camera at negative z. We store it z-up like the
//! simtrax sample (`x' = 556 - x`, `y' = z`, `z' = y`: a proper rotation, so the red wall stays
//! on the left as in the photograph), which makes the simtrax `cornell.view`/`.light` files
//! and this scene's camera agree.

use super::{geometric_normal, Material, PointLight, Scene, Vec3, View};

/// Published corner data (x, y-up, z) in millimetres, as quads.
const FLOOR: [Vec3; 4] = [
    [552.8, 0.0, 0.0],
    [0.0, 0.0, 0.0],
    [0.0, 0.0, 559.2],
    [549.6, 0.0, 559.2],
];
const CEILING: [Vec3; 4] = [
    [556.0, 548.8, 0.0],
    [556.0, 548.8, 559.2],
    [0.0, 548.8, 559.2],
    [0.0, 548.8, 0.0],
];
const BACK_WALL: [Vec3; 4] = [
    [549.6, 0.0, 559.2],
    [0.0, 0.0, 559.2],
    [0.0, 548.8, 559.2],
    [556.0, 548.8, 559.2],
];
const RIGHT_WALL: [Vec3; 4] = [
    [0.0, 0.0, 559.2],
    [0.0, 0.0, 0.0],
    [0.0, 548.8, 0.0],
    [0.0, 548.8, 559.2],
];
const LEFT_WALL: [Vec3; 4] = [
    [552.8, 0.0, 0.0],
    [549.6, 0.0, 559.2],
    [556.0, 548.8, 559.2],
    [556.0, 548.8, 0.0],
];
// The light sits 0.1 mm below the ceiling so the two surfaces do not coincide.
const LIGHT: [Vec3; 4] = [
    [343.0, 548.7, 227.0],
    [343.0, 548.7, 332.0],
    [213.0, 548.7, 332.0],
    [213.0, 548.7, 227.0],
];
const SHORT_BLOCK: [[Vec3; 4]; 5] = [
    [
        [130.0, 165.0, 65.0],
        [82.0, 165.0, 225.0],
        [240.0, 165.0, 272.0],
        [290.0, 165.0, 114.0],
    ],
    [
        [290.0, 0.0, 114.0],
        [290.0, 165.0, 114.0],
        [240.0, 165.0, 272.0],
        [240.0, 0.0, 272.0],
    ],
    [
        [130.0, 0.0, 65.0],
        [130.0, 165.0, 65.0],
        [290.0, 165.0, 114.0],
        [290.0, 0.0, 114.0],
    ],
    [
        [82.0, 0.0, 225.0],
        [82.0, 165.0, 225.0],
        [130.0, 165.0, 65.0],
        [130.0, 0.0, 65.0],
    ],
    [
        [240.0, 0.0, 272.0],
        [240.0, 165.0, 272.0],
        [82.0, 165.0, 225.0],
        [82.0, 0.0, 225.0],
    ],
];
const TALL_BLOCK: [[Vec3; 4]; 5] = [
    [
        [423.0, 330.0, 247.0],
        [265.0, 330.0, 296.0],
        [314.0, 330.0, 456.0],
        [472.0, 330.0, 406.0],
    ],
    [
        [423.0, 0.0, 247.0],
        [423.0, 330.0, 247.0],
        [472.0, 330.0, 406.0],
        [472.0, 0.0, 406.0],
    ],
    [
        [472.0, 0.0, 406.0],
        [472.0, 330.0, 406.0],
        [314.0, 330.0, 456.0],
        [314.0, 0.0, 456.0],
    ],
    [
        [314.0, 0.0, 456.0],
        [314.0, 330.0, 456.0],
        [265.0, 330.0, 296.0],
        [265.0, 0.0, 296.0],
    ],
    [
        [265.0, 0.0, 296.0],
        [265.0, 330.0, 296.0],
        [423.0, 330.0, 247.0],
        [423.0, 0.0, 247.0],
    ],
];

const WHITE: u32 = 0;
const RED: u32 = 1;
const GREEN: u32 = 2;
const LIGHT_MAT: u32 = 3;

/// Maps the published y-up coordinates to the stored z-up frame.
fn to_z_up(p: Vec3) -> Vec3 {
    [556.0 - p[0], p[2], p[1]]
}

fn dot(a: Vec3, b: Vec3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Adds a quad as two triangles with flat normals facing towards (`inward`) or away from
/// the point `toward`.
fn quad(scene: &mut Scene, q: &[Vec3; 4], material: u32, toward: Vec3, inward: bool) {
    let q = q.map(to_z_up);
    let toward = to_z_up(toward);
    for tri in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
        let mut n = geometric_normal(&tri);
        let c = super::sub(toward, tri[0]);
        if (dot(n, c) > 0.0) != inward {
            n = n.map(|x| -x);
        }
        scene.triangles.push(tri);
        scene.normals.push([n; 3]);
        scene.texcoords.push([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
        scene.material_ids.push(material);
    }
}

fn material(name: &str, diffuse: Vec3, emission: Vec3) -> Material {
    Material {
        name: name.into(),
        diffuse,
        specular: [0.0; 3],
        emission,
        shininess: 0.0,
        illum: 1,
    }
}

/// The embedded Cornell box: 32 triangles, white/red/green walls, an emissive ceiling light,
/// a matching camera (the published one: eye 800 mm in front of the opening, 35 mm lens on
/// a 25 mm film, i.e. image-plane distance 2.8 for a [-1, 1] window) and a point light
/// under the ceiling light.
pub fn cornell_box() -> Scene {
    let view = View {
        eye: [278.0, -800.0, 273.0],
        gaze: [0.0, 1.0, 0.0],
        up: [0.0, 0.0, 1.0],
        aperture: 0.0,
        left: -1.0,
        right: 1.0,
        bottom: -1.0,
        top: 1.0,
        distance: 2.8,
    };
    let mut s = Scene::new("cornell", view);
    s.materials = vec![
        material("white", [0.73, 0.73, 0.73], [0.0; 3]),
        material("red", [0.65, 0.05, 0.05], [0.0; 3]),
        material("green", [0.12, 0.45, 0.15], [0.0; 3]),
        material("light", [0.78, 0.78, 0.78], [17.0, 12.0, 4.0]),
    ];
    let room: Vec3 = [278.0, 274.4, 279.6];
    quad(&mut s, &FLOOR, WHITE, room, true);
    quad(&mut s, &CEILING, WHITE, room, true);
    quad(&mut s, &BACK_WALL, WHITE, room, true);
    quad(&mut s, &RIGHT_WALL, GREEN, room, true);
    quad(&mut s, &LEFT_WALL, RED, room, true);
    quad(&mut s, &LIGHT, LIGHT_MAT, room, true);
    for f in &SHORT_BLOCK {
        quad(&mut s, f, WHITE, [186.0, 82.5, 168.5], false);
    }
    for f in &TALL_BLOCK {
        quad(&mut s, f, WHITE, [368.5, 165.0, 351.5], false);
    }
    s.point_lights = vec![PointLight {
        position: [278.0, 279.5, 540.0],
        color: [1.0; 3],
    }];
    s
}
