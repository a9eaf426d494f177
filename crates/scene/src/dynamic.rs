//! Objects the far field's bake never saw (the book, "Near and far"): meshes marked dynamic by
//! a glTF node's extras (`"nearfield": {"dynamic": true}`), by `--dynamic NAME` or by `--add
//! FILE`. The frame and the reference draw them; `nearfield bake` bakes [`Scene::baked_part`].

use crate::{Aabb, Scene};
use glam::{Mat4, Vec3};

/// Why `--dynamic` or `--add` cannot be applied.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DynamicError {
    #[error(
        "--dynamic {name}: {scene} names no nodes (OBJ and PLY files have none; use glTF node names)"
    )]
    NoNames { name: String, scene: String },
    #[error("--dynamic {name}: no node of {scene} is named so (its nodes: {known})")]
    Unknown {
        name: String,
        scene: String,
        known: String,
    },
    #[error("--add {spec}: {what}")]
    Add { spec: String, what: String },
}

/// Where `--add FILE@X,Y,Z[,S]` puts a model: the centre of its bounds' base at `at`, scaled
/// uniformly by `scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub at: Vec3,
    pub scale: f32,
}

impl Placement {
    /// Parses `X,Y,Z` or `X,Y,Z,S` (S > 0, default 1) of `--add` `spec`.
    pub fn parse(spec: &str, place: &str) -> Result<Self, DynamicError> {
        let bad = |what: &str| DynamicError::Add {
            spec: spec.to_string(),
            what: what.to_string(),
        };
        let v: Vec<f32> = place
            .split(',')
            .map(|x| x.trim().parse::<f32>())
            .collect::<Result<_, _>>()
            .map_err(|_| bad("expected FILE@X,Y,Z or FILE@X,Y,Z,SCALE"))?;
        if !(v.len() == 3 || v.len() == 4) || v.iter().any(|x| !x.is_finite()) {
            return Err(bad(
                "expected three finite coordinates and an optional scale",
            ));
        }
        let scale = v.get(3).copied().unwrap_or(1.0);
        if !(scale > 0.0 && scale <= 1e6) {
            return Err(bad("the scale must be in (0, 1e6]"));
        }
        Ok(Placement {
            at: Vec3::new(v[0], v[1], v[2]),
            scale,
        })
    }
}

impl Scene {
    /// Marks the meshes under the nodes named `names` dynamic; every name must match a node.
    pub fn mark_dynamic(&mut self, names: &[String]) -> Result<(), DynamicError> {
        for name in names {
            if self.meshes.iter().all(|m| m.nodes.is_empty()) {
                return Err(DynamicError::NoNames {
                    name: name.clone(),
                    scene: self.name.clone(),
                });
            }
            let mut found = false;
            for m in &mut self.meshes {
                if m.nodes.iter().any(|n| n == name) {
                    m.dynamic = true;
                    found = true;
                }
            }
            if !found {
                let mut known: Vec<&str> = self
                    .meshes
                    .iter()
                    .flat_map(|m| m.nodes.iter().map(String::as_str))
                    .collect();
                known.sort_unstable();
                known.dedup();
                let list = if known.len() > 12 {
                    format!("{}, … ({} in all)", known[..12].join(", "), known.len())
                } else {
                    known.join(", ")
                };
                return Err(DynamicError::Unknown {
                    name: crate::one_line(name),
                    scene: self.name.clone(),
                    known: crate::one_line(&list),
                });
            }
        }
        Ok(())
    }

    /// Adds `other`'s meshes (with their materials and textures) placed by `p`, dynamic, under
    /// a node named `name`. Its animation comes along (under a node that places it); its lights
    /// and cameras are not taken.
    pub fn add(&mut self, other: Scene, name: &str, p: Placement) {
        let bounds = other.bounds();
        let base = Vec3::new(
            0.5 * (bounds.min.x + bounds.max.x),
            bounds.min.y,
            0.5 * (bounds.min.z + bounds.max.z),
        );
        let world = Mat4::from_translation(p.at)
            * Mat4::from_scale(Vec3::splat(p.scale))
            * Mat4::from_translation(-base);
        // The model's animated nodes hang from one that places them, after this scene's nodes.
        let n0 = self.animation.nodes.len() as u32;
        let moves = !other.animation.is_empty();
        if moves {
            let mut placing = crate::animation::Node::at(name, p.at - p.scale * base);
            placing.scale = Vec3::splat(p.scale);
            self.animation.nodes.push(placing);
            for mut node in other.animation.nodes {
                node.parent = Some(node.parent.map_or(n0, |q| q + n0 + 1));
                self.animation.nodes.push(node);
            }
        }
        let (m0, t0) = (self.materials.len() as u32, self.textures.len());
        self.textures.extend(other.textures);
        for mut mat in other.materials {
            for t in [
                &mut mat.base_color_texture,
                &mut mat.metallic_roughness_texture,
                &mut mat.emissive_texture,
            ] {
                *t = t.map(|i| i + t0);
            }
            self.materials.push(mat);
        }
        for mut mesh in other.meshes {
            mesh.transform(world);
            mesh.material += m0;
            mesh.nodes.insert(0, name.to_string());
            mesh.dynamic = true;
            if let Some(m) = &mut mesh.motion {
                m.node += n0 + 1;
                (m.rest_positions, m.rest_normals) = m.posed(world);
            }
            if !moves {
                mesh.motion = None;
            }
            self.meshes.push(mesh);
        }
    }

    /// The scene without its dynamic meshes: what the far field is baked from.
    pub fn baked_part(&self) -> Scene {
        Scene {
            meshes: self.meshes.iter().filter(|m| !m.dynamic).cloned().collect(),
            ..self.clone()
        }
    }

    /// Whether any mesh is dynamic.
    pub fn has_dynamic(&self) -> bool {
        self.meshes.iter().any(|m| m.dynamic)
    }

    /// World bounds of the dynamic meshes.
    pub fn dynamic_bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        for m in self.meshes.iter().filter(|m| m.dynamic) {
            for p in &m.positions {
                b.grow(*p);
            }
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_mark_their_meshes_and_unknown_names_are_refused() {
        let mut s = crate::builtin::scene("cornell").unwrap();
        s.mark_dynamic(&["red".into()]).unwrap();
        let red: Vec<bool> = s.meshes.iter().map(|m| m.dynamic).collect();
        assert_eq!(red.iter().filter(|&&d| d).count(), 1);
        let e = s.mark_dynamic(&["chair".into()]).unwrap_err();
        assert!(e.to_string().contains("no node"), "{e}");
        assert!(e.to_string().contains("red"), "{e}");
        let mut bare = s.clone();
        for m in &mut bare.meshes {
            m.nodes.clear();
        }
        let e = bare.mark_dynamic(&["red".into()]).unwrap_err();
        assert!(matches!(e, DynamicError::NoNames { .. }), "{e}");
    }

    #[test]
    fn the_variants_bake_without_their_box() {
        for name in ["cornell-dynamic", "two-rooms-dynamic"] {
            let s = crate::builtin::scene(name).unwrap();
            let base = crate::builtin::scene(name.trim_end_matches("-dynamic")).unwrap();
            assert!(s.has_dynamic(), "{name}");
            assert_eq!(s.baked_part().triangle_count(), base.triangle_count());
            assert!(s.triangle_count() > base.triangle_count());
        }
    }

    #[test]
    fn an_added_model_moves_as_its_animation_says_where_it_is_placed() {
        let mut s = crate::builtin::scene("plane").unwrap();
        let other = crate::builtin::scene("columns-moving").unwrap();
        let p = Placement::parse("x", "3,0.5,-2,0.5").unwrap();
        // The bounds of the moving meshes at time t.
        let (mut alone, moved) = (other.clone(), |s: &Scene, t: f32| {
            let mut s = s.clone();
            s.pose(t);
            let mut b = crate::Aabb::EMPTY;
            for m in s.meshes.iter().filter(|m| m.motion.is_some()) {
                m.positions.iter().for_each(|p| b.grow(*p));
            }
            b
        });
        s.add(other, "columns", p);
        assert!(s.moves());
        alone.pose(0.0);
        // The ball at half scale rolls half as far: its bounds move by half of its own.
        let (a0, a1) = (moved(&alone, 0.0), moved(&alone, 2.0));
        let (b0, b1) = (moved(&s, 0.0), moved(&s, 2.0));
        let (da, db) = (a1.center() - a0.center(), b1.center() - b0.center());
        assert!((db - 0.5 * da).length() < 1e-4, "{da} {db}");
        assert!((b0.extent() - 0.5 * a0.extent()).length() < 1e-4);
    }

    #[test]
    fn an_added_model_stands_where_it_is_placed() {
        let mut s = crate::builtin::scene("plane").unwrap();
        let other = crate::builtin::scene("cornell").unwrap();
        let p = Placement::parse("x", "3,0.5,-2,0.5").unwrap();
        s.add(other, "cornell", p);
        let b = s.dynamic_bounds();
        // The box is 2 m wide and tall: at half scale 1 m, its base centred on (3, 0.5, −2).
        assert!(
            (b.min.y - 0.5).abs() < 1e-5 && (b.max.y - 1.5).abs() < 1e-5,
            "{b:?}"
        );
        assert!((0.5 * (b.min.x + b.max.x) - 3.0).abs() < 1e-5, "{b:?}");
        assert!(Placement::parse("x", "1,2").is_err());
        assert!(Placement::parse("x", "1,2,3,0").is_err());
        assert!(Placement::parse("x", "1,2,nan").is_err());
    }
}
