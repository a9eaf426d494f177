//! Built-in scenes that need no files. Each has a default camera and environment; all are in
//! metres, +Y up, materials rough diffuse.
//!
//! | name | what |
//! |---|---|
//! | `cornell` | open-top Cornell box (white floor and back wall, red left wall, green right wall, a tall and a short box), lit by the sky through the open top; the default scene |
//! | `boxes` | three boxes on a plane, a pink point light on the left and a turquoise one on the right (S3HO Fig. 5) |
//! | `city` | box skyscrapers on a ground plane under the sky with sun (S3HO Fig. 6) |
//! | `plane` | one 400 m × 400 m plane: nothing occludes anything |
//! | `wall` | a 400 m floor meeting a 200 m wall at 90° along the line y = 0, z = 0 |
//! | `closed-box` | a closed 4 × 3 × 4 m room with a point light; the camera is inside |
//! | `gap` | three thin posts (4 × 4 cm, 1.5 m tall) 0.3 m in front of a wall under the sky: the gap behind a post lies behind it from the camera (SSDO Fig. 5) |
//! | `columns` | a white column hiding a pink column behind it from the camera, on a floor under the sky and a sun from the right (SSDO Fig. 7) |
//! | `contact` | a 4 cm cube and a 2 cm rod on a 6 m plane under a low sun: the shadow map's bias loses their contact shadows (SSDO Fig. 9) |
//! | `two-rooms` | two 3 × 2.5 × 3 m rooms side by side, a 20 cm wall between them; the left one is open to the sky, the right one closed (no light reaches it): the far field's leak test |
//! | `cornell-dynamic` | `cornell` with a yellow 0.4 m box on the floor, front left, that the far field's bake leaves out (dynamic) |
//! | `two-rooms-dynamic` | `two-rooms` with a 0.6 m box on the open room's floor, dynamic |
//! | `cornell-moving` | `cornell` with a yellow 0.24 m box sliding 1.45 m across the front of the floor in 2 s, then standing still (3 s in all) |
//! | `columns-moving` | `columns` with a 0.25 m ball rolling 3.2 m in front of the columns in 2 s, then standing still (3 s in all) |
//! | `rolling-ball` | that ball alone, rolling 3.2 m along +X from the origin: `--add builtin:rolling-ball@X,Y,Z[,S]` rolls it through another scene |

mod builder;

use crate::Track;
use crate::{Camera, EnvSource, Light, LightKind, Material, Scene, SceneError};
use builder::Builder;
use glam::{Quat, Vec2, Vec3, Vec3Swizzles};

/// Names of the built-in scenes, in the order shown to users.
pub const NAMES: &[&str] = &[
    "cornell",
    "boxes",
    "city",
    "plane",
    "wall",
    "closed-box",
    "gap",
    "columns",
    "contact",
    "two-rooms",
    "cornell-dynamic",
    "two-rooms-dynamic",
    "cornell-moving",
    "columns-moving",
    "rolling-ball",
];

/// Builds the named built-in scene.
pub fn scene(name: &str) -> Result<Scene, SceneError> {
    let s = match name {
        "cornell" => cornell(),
        "boxes" => boxes(),
        "city" => city(),
        "plane" => plane(),
        "wall" => wall(),
        "closed-box" => closed_box(),
        "gap" => gap(),
        "columns" => columns(),
        "contact" => contact(),
        "two-rooms" => two_rooms(),
        "cornell-dynamic" => cornell_dynamic(),
        "two-rooms-dynamic" => two_rooms_dynamic(),
        "cornell-moving" => cornell_moving(),
        "columns-moving" => columns_moving(),
        "rolling-ball" => rolling_ball(),
        _ => {
            return Err(SceneError::UnknownBuiltin {
                name: name.into(),
                known: NAMES.join(", "),
            });
        }
    };
    Ok(s)
}

const WHITE: Vec3 = Vec3::new(0.73, 0.73, 0.73);

/// The open-top Cornell box: 2 m cube without ceiling and front wall, reflectances of the
/// classic Cornell box measurements (white 0.73, red (0.63, 0.065, 0.05), green (0.14, 0.45, 0.091)).
fn cornell() -> Scene {
    let mut b = Builder::new("cornell");
    let white = b.material(Material::diffuse("white", WHITE));
    let red = b.material(Material::diffuse("red", Vec3::new(0.63, 0.065, 0.05)));
    let green = b.material(Material::diffuse("green", Vec3::new(0.14, 0.45, 0.091)));
    b.floor(white, Vec2::splat(-1.0), Vec2::splat(1.0), 0.0, false);
    // Back wall z = −1 facing +Z.
    b.quad(
        white,
        [
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(1.0, 2.0, -1.0),
            Vec3::new(-1.0, 2.0, -1.0),
        ],
    );
    // Left wall x = −1 facing +X (red), right wall x = +1 facing −X (green).
    b.quad(
        red,
        [
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(-1.0, 2.0, -1.0),
            Vec3::new(-1.0, 2.0, 1.0),
        ],
    );
    b.quad(
        green,
        [
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(1.0, 2.0, 1.0),
            Vec3::new(1.0, 2.0, -1.0),
        ],
    );
    b.block(
        white,
        Vec2::new(-0.33, -0.3),
        Vec3::new(0.6, 1.2, 0.6),
        0.0,
        17.0,
    );
    b.block(
        white,
        Vec2::new(0.35, 0.35),
        Vec3::new(0.6, 0.6, 0.6),
        0.0,
        -18.0,
    );
    b.finish(
        Camera::new(Vec3::new(0.0, 1.0, 3.9), Vec3::new(0.0, 0.9, 0.0), 38.0),
        EnvSource::Sky,
    )
}

fn boxes() -> Scene {
    let mut b = Builder::new("boxes");
    let ground = b.material(Material::diffuse("ground", Vec3::splat(0.7)));
    let boxes = b.material(Material::diffuse("boxes", Vec3::splat(0.75)));
    b.floor(ground, Vec2::splat(-10.0), Vec2::splat(10.0), 0.0, false);
    b.block(
        boxes,
        Vec2::new(-1.6, 0.2),
        Vec3::new(1.0, 1.0, 1.0),
        0.0,
        20.0,
    );
    b.block(
        boxes,
        Vec2::new(0.0, -0.4),
        Vec3::new(0.8, 1.8, 0.8),
        0.0,
        -10.0,
    );
    b.block(
        boxes,
        Vec2::new(1.6, 0.3),
        Vec3::new(1.2, 0.6, 1.2),
        0.0,
        35.0,
    );
    let point = |position: Vec3, color: Vec3| Light {
        kind: LightKind::Point { position },
        color,
        intensity: 40.0,
        range: None,
    };
    b.scene.lights = vec![
        point(Vec3::new(-4.5, 2.5, 1.0), Vec3::new(1.0, 0.35, 0.7)),
        point(Vec3::new(4.5, 2.5, 1.0), Vec3::new(0.2, 0.9, 0.85)),
    ];
    b.finish(
        Camera::new(Vec3::new(0.0, 3.2, 6.5), Vec3::new(0.0, 0.6, 0.0), 45.0),
        EnvSource::Constant(Vec3::splat(0.15)),
    )
}

fn city() -> Scene {
    let mut b = Builder::new("city");
    let ground = b.material(Material::diffuse("ground", Vec3::splat(0.5)));
    let towers = b.material(Material::diffuse("towers", Vec3::new(0.7, 0.68, 0.64)));
    b.floor(ground, Vec2::splat(-60.0), Vec2::splat(60.0), 0.0, false);
    // A 7×7 grid on a 9 m pitch with heights from a fixed linear congruential sequence, so the
    // city is the same on every machine.
    let mut state: u32 = 12345;
    let mut rand = || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    for i in -3..=3 {
        for j in -3..=3 {
            let w = 4.0 + 2.5 * rand();
            let d = 4.0 + 2.5 * rand();
            let h = 5.0 + 25.0 * rand() * rand();
            b.block(
                towers,
                Vec2::new(i as f32 * 9.0, j as f32 * 9.0),
                Vec3::new(w, h, d),
                0.0,
                0.0,
            );
        }
    }
    b.finish(
        Camera::new(Vec3::new(38.0, 32.0, 52.0), Vec3::new(0.0, 3.0, 0.0), 45.0),
        EnvSource::Sky,
    )
}

fn plane() -> Scene {
    let mut b = Builder::new("plane");
    let ground = b.material(Material::diffuse("ground", Vec3::splat(0.8)));
    b.floor(ground, Vec2::splat(-200.0), Vec2::splat(200.0), 0.0, false);
    b.finish(
        Camera::new(Vec3::new(0.0, 2.0, 5.0), Vec3::new(0.0, 0.0, -1.0), 60.0),
        EnvSource::Sky,
    )
}

fn wall() -> Scene {
    let mut b = Builder::new("wall");
    let floor = b.material(Material::diffuse("floor", Vec3::splat(0.8)));
    let wall = b.material(Material::diffuse("wall", Vec3::splat(0.8)));
    b.floor(
        floor,
        Vec2::new(-200.0, 0.0),
        Vec2::new(200.0, 400.0),
        0.0,
        false,
    );
    b.quad(
        wall,
        [
            Vec3::new(-200.0, 0.0, 0.0),
            Vec3::new(200.0, 0.0, 0.0),
            Vec3::new(200.0, 200.0, 0.0),
            Vec3::new(-200.0, 200.0, 0.0),
        ],
    );
    b.finish(
        Camera::new(Vec3::new(2.5, 2.0, 5.0), Vec3::new(0.0, 0.6, 0.0), 60.0),
        EnvSource::Sky,
    )
}

fn closed_box() -> Scene {
    let mut b = Builder::new("closed-box");
    let walls = b.material(Material::diffuse("walls", Vec3::splat(0.7)));
    let floor = b.material(Material::diffuse("floor", Vec3::new(0.6, 0.55, 0.5)));
    let (x, y, z) = (2.0, 3.0, 2.0);
    b.floor(floor, Vec2::new(-x, -z), Vec2::new(x, z), 0.0, false);
    b.floor(walls, Vec2::new(-x, -z), Vec2::new(x, z), y, true);
    let v = Vec3::new;
    // Inward-facing walls: −Z wall faces +Z, +Z wall faces −Z, −X faces +X, +X faces −X.
    b.quad(
        walls,
        [v(-x, 0., -z), v(x, 0., -z), v(x, y, -z), v(-x, y, -z)],
    );
    b.quad(walls, [v(x, 0., z), v(-x, 0., z), v(-x, y, z), v(x, y, z)]);
    b.quad(
        walls,
        [v(-x, 0., z), v(-x, 0., -z), v(-x, y, -z), v(-x, y, z)],
    );
    b.quad(walls, [v(x, 0., -z), v(x, 0., z), v(x, y, z), v(x, y, -z)]);
    let blocks = b.material(Material::diffuse("block", Vec3::splat(0.75)));
    b.block(
        blocks,
        Vec2::new(0.4, -0.8),
        Vec3::new(0.8, 0.8, 0.8),
        0.0,
        25.0,
    );
    b.scene.lights = vec![Light {
        kind: LightKind::Point {
            position: Vec3::new(0.0, 2.6, 0.0),
        },
        color: Vec3::ONE,
        intensity: 12.0,
        range: None,
    }];
    b.finish(
        Camera::new(Vec3::new(-1.0, 1.6, 1.8), Vec3::new(0.3, 0.8, -1.5), 70.0),
        EnvSource::Sky,
    )
}

/// `cornell` with a yellow 0.4 m box on the floor, front left, left out of the far field's bake:
/// its contact shadow and bounce are what only the near field can add.
fn cornell_dynamic() -> Scene {
    let mut s = cornell();
    let mut b = Builder { scene: s };
    let m = b.dynamic_material(Material::diffuse("dynamic box", Vec3::new(0.75, 0.6, 0.2)));
    b.block(m, Vec2::new(-0.5, 0.45), Vec3::splat(0.4), 0.0, 30.0);
    s = b.scene;
    s.name = "builtin:cornell-dynamic".into();
    s
}

/// `two-rooms` with a 0.6 m box on the open room's floor, left out of the far field's bake.
fn two_rooms_dynamic() -> Scene {
    let mut b = Builder { scene: two_rooms() };
    let m = b.dynamic_material(Material::diffuse("dynamic box", Vec3::splat(0.75)));
    b.block(m, Vec2::new(-1.6, -0.4), Vec3::splat(0.6), 0.0, 20.0);
    let mut s = b.scene;
    s.name = "builtin:two-rooms-dynamic".into();
    s
}

/// How long the moving variants' objects move, and how long they then stand still (s).
const MOVING: f32 = 2.0;
const STANDING: f32 = 1.0;

/// `cornell` with a yellow box sliding across the front of the floor, in front of the short box,
/// then standing still: what its contact shadow and bounce do in motion, and the ghost it may
/// leave where it was.
fn cornell_moving() -> Scene {
    let (from, to) = (Vec3::new(-0.75, 0.0, 0.86), Vec3::new(0.7, 0.0, 0.86));
    let mut b = Builder { scene: cornell() };
    let m = b.dynamic_material(Material::diffuse("sliding box", Vec3::new(0.75, 0.6, 0.2)));
    b.block(m, from.xz(), Vec3::splat(0.24), 0.0, 0.0);
    let mut node = crate::animation::Node::at("sliding box", from);
    node.translations = Some(Track::linear(&[
        (0.0, from),
        (MOVING, to),
        (MOVING + STANDING, to),
    ]));
    moving(b, m, node, "cornell-moving")
}

/// `columns` with a ball rolling along in front of the columns, then standing still.
fn columns_moving() -> Scene {
    roll(
        Builder { scene: columns() },
        Vec3::new(-1.6, 0.0, 0.7),
        "columns-moving",
    )
}

/// The ball of `columns-moving` alone, rolling from the origin: a model to `--add`.
fn rolling_ball() -> Scene {
    let mut s = roll(Builder::new("rolling-ball"), Vec3::ZERO, "rolling-ball");
    s.meshes.retain(|m| !m.indices.is_empty());
    s.cameras = vec![Camera::new(
        Vec3::new(1.6, 1.2, 4.0),
        Vec3::new(1.6, 0.25, 0.0),
        45.0,
    )];
    s.default_env = EnvSource::Sky;
    s
}

/// `b`'s scene with a 0.25 m ball resting on y = `start.y` at `start` rolling 3.2 m along +X in
/// 2 s, then standing still for 1 s.
fn roll(mut b: Builder, start: Vec3, name: &str) -> Scene {
    let radius = 0.25;
    let from = start + Vec3::Y * radius;
    let to = from + Vec3::X * 3.2;
    let m = b.dynamic_material(Material::diffuse(
        "rolling ball",
        Vec3::new(0.3, 0.55, 0.85),
    ));
    b.sphere(m, from, radius, 12);
    let mut node = crate::animation::Node::at("rolling ball", from);
    // Rolling without slipping: a turn of −d/r about +Z after d metres along +X, keyed densely
    // enough that each step turns less than half a turn.
    let steps = 16;
    let keys: Vec<(f32, f32)> = (0..=steps)
        .map(|i| {
            let s = i as f32 / steps as f32;
            (s * MOVING, s * (to.x - from.x))
        })
        .collect();
    let at = |d: f32| from + Vec3::X * d;
    let mut translations: Vec<(f32, Vec3)> = keys.iter().map(|&(t, d)| (t, at(d))).collect();
    let mut rotations: Vec<(f32, Quat)> = keys
        .iter()
        .map(|&(t, d)| (t, Quat::from_rotation_z(-d / radius)))
        .collect();
    translations.push((MOVING + STANDING, to));
    rotations.push((MOVING + STANDING, rotations[steps].1));
    node.translations = Some(Track::linear(&translations));
    node.rotations = Some(Track::linear(&rotations));
    moving(b, m, node, name)
}

/// The scene of `b` with mesh `m` following `node`, the one animated node.
fn moving(b: Builder, m: u32, node: crate::animation::Node, name: &str) -> Scene {
    let mut s = b.scene;
    s.animation = crate::Animation { nodes: vec![node] };
    s.meshes[m as usize].follow(0);
    s.name = format!("builtin:{name}");
    s
}

/// Two rooms side by side along x, sharing a 20 cm wall (x = ±0.1): the left one
/// (x ∈ [−3.2, −0.1]) has no ceiling and sees the sky and its sun, the right one
/// (x ∈ [0.1, 3.2]) is closed on every side, so that no light reaches it. A probe volume must
/// not carry the lit room's light through the wall.
fn two_rooms() -> Scene {
    let mut b = Builder::new("two-rooms");
    let walls = b.material(Material::diffuse("walls", Vec3::splat(0.7)));
    let floor = b.material(Material::diffuse("floor", Vec3::new(0.6, 0.55, 0.5)));
    let (x, y, z, t) = (3.2, 2.5, 1.5, 0.1);
    let v = Vec3::new;
    b.floor(floor, Vec2::new(-x, -z), Vec2::new(x, z), 0.0, false);
    // The dark room's ceiling, facing down.
    b.floor(walls, Vec2::new(t, -z), Vec2::new(x, z), y, true);
    // Inward-facing outer walls: −Z faces +Z, +Z faces −Z, −X faces +X, +X faces −X.
    b.quad(
        walls,
        [v(-x, 0., -z), v(x, 0., -z), v(x, y, -z), v(-x, y, -z)],
    );
    b.quad(walls, [v(x, 0., z), v(-x, 0., z), v(-x, y, z), v(x, y, z)]);
    b.quad(
        walls,
        [v(-x, 0., z), v(-x, 0., -z), v(-x, y, -z), v(-x, y, z)],
    );
    b.quad(walls, [v(x, 0., -z), v(x, 0., z), v(x, y, z), v(x, y, -z)]);
    // The shared wall: a solid 2t thick, as tall as the rooms.
    b.block(walls, Vec2::ZERO, Vec3::new(2.0 * t, y, 2.0 * z), 0.0, 0.0);
    b.finish(
        Camera::new(Vec3::new(-2.9, 1.6, 1.2), Vec3::new(-0.1, 0.8, -0.6), 70.0),
        EnvSource::Sky,
    )
}

/// SSDO Fig. 5: three thin posts (4 × 4 cm, 1.5 m tall) stand 0.3 m in front of a wall; points
/// of the gap between a post and the wall lie behind the post from the camera, so one depth
/// layer takes them for the inside of a solid (a dark halo on the wall and the floor around each
/// post), while rays from the wall through the gap mostly reach the sky.
fn gap() -> Scene {
    let mut b = Builder::new("gap");
    let floor = b.material(Material::diffuse("floor", Vec3::splat(0.7)));
    let wall = b.material(Material::diffuse("wall", Vec3::splat(0.75)));
    let posts = b.material(Material::diffuse("posts", Vec3::new(0.7, 0.6, 0.45)));
    // The floor ends at the wall: nothing lies behind the wall for a second layer to find.
    b.floor(
        floor,
        Vec2::new(-3.0, -1.0),
        Vec2::new(3.0, 3.0),
        0.0,
        false,
    );
    b.quad(
        wall,
        [
            Vec3::new(-3.0, 0.0, -1.0),
            Vec3::new(3.0, 0.0, -1.0),
            Vec3::new(3.0, 2.5, -1.0),
            Vec3::new(-3.0, 2.5, -1.0),
        ],
    );
    for x in [-0.6, 0.0, 0.6] {
        b.block(
            posts,
            Vec2::new(x, -0.7),
            Vec3::new(0.04, 1.5, 0.04),
            0.0,
            0.0,
        );
    }
    b.finish(
        Camera::new(Vec3::new(0.0, 1.0, 2.2), Vec3::new(0.0, 0.6, -1.0), 40.0),
        EnvSource::Sky,
    )
}

/// SSDO Fig. 7: a white column (0.6 × 1.6 × 0.6 m) hides a pink one (0.35 × 1.2 × 0.35 m, 0.6 m
/// behind it) from the camera; the floor beside the pink column is in view, and a sun from the
/// right lights the pink column's right face.
fn columns() -> Scene {
    let mut b = Builder::new("columns");
    let floor = b.material(Material::diffuse("floor", Vec3::splat(0.7)));
    let white = b.material(Material::diffuse("white", WHITE));
    let pink = b.material(Material::diffuse("pink", Vec3::new(0.9, 0.2, 0.55)));
    b.floor(floor, Vec2::splat(-3.0), Vec2::splat(3.0), 0.0, false);
    b.block(
        white,
        Vec2::new(0.0, 0.0),
        Vec3::new(0.6, 1.6, 0.6),
        0.0,
        0.0,
    );
    b.block(
        pink,
        Vec2::new(0.0, -0.6),
        Vec3::new(0.35, 1.2, 0.35),
        0.0,
        0.0,
    );
    b.scene.lights = vec![Light {
        kind: LightKind::Directional {
            direction: Vec3::new(-0.85, -0.45, 0.25).normalize(),
            angular_radius: 0.0,
        },
        color: Vec3::ONE,
        intensity: 3.0,
        range: None,
    }];
    b.finish(
        Camera::new(Vec3::new(0.0, 0.9, 4.0), Vec3::new(0.0, 0.4, 0.0), 40.0),
        EnvSource::Sky,
    )
}

/// SSDO Fig. 9: small objects on a plane under a sun 25° above the horizon, seen from close by.
fn contact() -> Scene {
    let mut b = Builder::new("contact");
    let floor = b.material(Material::diffuse("floor", Vec3::splat(0.75)));
    let objects = b.material(Material::diffuse("objects", Vec3::new(0.6, 0.6, 0.7)));
    b.floor(floor, Vec2::splat(-3.0), Vec2::splat(3.0), 0.0, false);
    b.block(objects, Vec2::new(0.0, 0.0), Vec3::splat(0.04), 0.0, 30.0);
    b.block(
        objects,
        Vec2::new(0.12, 0.05),
        Vec3::new(0.02, 0.1, 0.02),
        0.0,
        0.0,
    );
    let elevation = 25f32.to_radians();
    b.scene.lights = vec![Light {
        kind: LightKind::Directional {
            direction: Vec3::new(
                -elevation.cos() * 0.8,
                -elevation.sin(),
                -elevation.cos() * 0.6,
            )
            .normalize(),
            angular_radius: 0.0,
        },
        color: Vec3::ONE,
        intensity: 3.0,
        range: None,
    }];
    b.finish(
        Camera::new(Vec3::new(0.05, 0.22, 0.42), Vec3::new(0.03, 0.0, 0.0), 40.0),
        EnvSource::Constant(Vec3::splat(0.1)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_is_valid_and_faces_the_camera() {
        for name in NAMES {
            let s = scene(name).unwrap();
            s.validate(std::path::Path::new(name)).unwrap();
            assert!(s.triangle_count() >= 2, "{name}");
            // Winding agrees with the stored normals (a ball's smooth normals lean up to half a
            // facet's 15° from its faces; every other face is flat).
            for m in &s.meshes {
                for t in &m.indices {
                    let [a, bb, c] = t.map(|i| m.positions[i as usize]);
                    let g = (bb - a).cross(c - a).normalize();
                    let flat = if m.name == "rolling ball" {
                        0.95
                    } else {
                        0.999
                    };
                    assert!(g.dot(m.normals[t[0] as usize]) > flat, "{name}");
                }
            }
            s.default_camera().validate().unwrap();
        }
        assert!(scene("nope").is_err());
    }

    #[test]
    fn closed_box_is_closed() {
        // Every edge of the room's shell is shared by exactly two triangles.
        let s = scene("closed-box").unwrap();
        let mut edges = std::collections::HashMap::new();
        let key = |p: Vec3| (p * 1000.0).round().as_ivec3().to_array();
        for m in s.meshes.iter().take(2) {
            for t in &m.indices {
                for k in 0..3 {
                    let (a, c) = (
                        key(m.positions[t[k] as usize]),
                        key(m.positions[t[(k + 1) % 3] as usize]),
                    );
                    *edges
                        .entry(if a < c { (a, c) } else { (c, a) })
                        .or_insert(0) += 1;
                }
            }
        }
        assert!(edges.values().all(|&n| n == 2), "{edges:?}");
    }
}
