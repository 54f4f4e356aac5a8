//! The `mix` material (pbrt-v4's `MixMaterial`): at each hit, one of two
//! named materials, the second with probability `amount`.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `materials` | string[2] | — (required) | the two named materials |
//! | `amount` | float texture | 0.5 | how often the second is chosen |
//!
//! As pbrt-v4, the choice is not a blend of the two BSDFs: an amount ≤ 0
//! gives the first material, ≥ 1 the second, and between, the second when
//! a hash u ∈ [0, 1) of the hit point and ω_o satisfies amount ≥ u (a
//! deterministic choice per point and direction, so the same ray always
//! sees the same material). pbrt-v4 also hashes the two materials'
//! addresses, which differ from run to run; rpbrt hashes their indices
//! among the scene's materials instead. A mix may name other mixes (not
//! itself, directly or through others).
//!
//! The two materials are copied into the mix when the scene is built
//! ([`resolve`]), after all materials are made, so the BSDF is found
//! without the scene's material table.

use super::Material;
use crate::error::{scene_error, Result};
use crate::interaction::SurfaceInteraction;
use crate::math::hash::hash_words;
use crate::textures::{FloatTexture, TextureEvalContext, TextureParams};
use pbrt_parser::Location;
use std::collections::HashMap;

#[derive(Clone, Debug)]
pub struct MixMaterial {
    /// The two materials' names, and where they were given.
    names: [String; 2],
    names_at: Location,
    /// Indices of the two materials among the scene's, once resolved.
    indices: [u32; 2],
    /// The two materials, once resolved (empty before).
    materials: Vec<Material>,
    amount: FloatTexture,
}

impl MixMaterial {
    /// Reads the parameters; the materials are found later by [`resolve`].
    pub fn create(tp: &TextureParams, loc: &Location) -> Result<MixMaterial> {
        let found = tp
            .params
            .find("materials", &[pbrt_parser::ParamType::String])?;
        let Some((names, names_at)) = found.map(|p| (p.strings().to_vec(), p.location.clone()))
        else {
            return scene_error(
                "mix: \"materials\" (two named materials) must be given",
                loc,
            );
        };
        let [first, second] = names.as_slice() else {
            return scene_error(
                format!(
                    "mix: \"materials\" must name two materials, not {}",
                    names.len()
                ),
                &names_at,
            );
        };
        Ok(MixMaterial {
            names: [first.to_string(), second.to_string()],
            names_at,
            indices: [0; 2],
            materials: Vec::new(),
            amount: tp.float_texture("amount", 0.5)?,
        })
    }

    /// The two materials (empty before [`resolve`]).
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// The material of the hit `si`, textures evaluated in `ctx`.
    pub fn choose(&self, si: &SurfaceInteraction, ctx: &TextureEvalContext) -> &Material {
        let [first, second] = match self.materials.as_slice() {
            [a, b] => [a, b],
            // Not resolved: the build always resolves, so this is not
            // reached; no BSDF (the ray passes) rather than a panic.
            _ => return &Material::Interface,
        };
        let amount = self.amount.evaluate(ctx);
        if amount <= 0.0 {
            return first;
        }
        if amount >= 1.0 {
            return second;
        }
        let (p, wo) = (si.p, si.wo);
        let words = [
            p.x.to_bits(),
            p.y.to_bits(),
            p.z.to_bits(),
            wo.x.to_bits(),
            wo.y.to_bits(),
            wo.z.to_bits(),
            self.indices[0],
            self.indices[1],
        ];
        let u = (hash_words(&words) as u32) as f32 * (1.0 / 4_294_967_296.0);
        if amount < u {
            first
        } else {
            second
        }
    }
}

/// Gives every mix among `materials` copies of the two materials it names
/// (`named`: each named material's index), mixes within mixes resolved
/// first. A name that is not a named material, or a mix that contains
/// itself, is an error at its `materials` parameter; so is a mix of a
/// hair material of the dual model, whose fibre the shape must be built
/// for.
pub fn resolve(materials: &mut [Material], named: &HashMap<&str, u32>) -> Result<()> {
    // Depth-first, so that a mix copies resolved mixes.
    fn resolve_one(
        i: usize,
        materials: &mut [Material],
        named: &HashMap<&str, u32>,
        visiting: &mut Vec<usize>,
    ) -> Result<()> {
        let (names, at) = match &materials[i] {
            Material::Mix(m) if m.materials.is_empty() => (m.names.clone(), m.names_at.clone()),
            _ => return Ok(()),
        };
        if visiting.contains(&i) {
            return scene_error("mix: the material contains itself", &at);
        }
        visiting.push(i);
        let mut indices = [0u32; 2];
        for (index, name) in indices.iter_mut().zip(&names) {
            let Some(&j) = named.get(name.as_str()) else {
                return scene_error(
                    format!("mix: named material \"{name}\" is not defined"),
                    &at,
                );
            };
            resolve_one(j as usize, materials, named, visiting)?;
            if materials[j as usize].dual_hair().is_some() {
                return scene_error(
                    format!("mix: \"{name}\" is a hair material of the dual model (ellipse or diffraction), which a mix cannot hold"),
                    &at,
                );
            }
            *index = j;
        }
        visiting.pop();
        let copies = indices.map(|j| materials[j as usize].clone());
        if let Material::Mix(m) = &mut materials[i] {
            m.indices = indices;
            m.materials = copies.into();
        }
        Ok(())
    }
    let mut visiting = Vec::new();
    for i in 0..materials.len() {
        resolve_one(i, materials, named, &mut visiting)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::Spectrum;
    use crate::textures::SpectrumTexture;
    use glam::Vec3;

    fn diffuse(r: f32) -> Material {
        Material::Diffuse {
            reflectance: SpectrumTexture::Constant(Spectrum::Constant(r)),
        }
    }

    fn mix(a: &str, b: &str, amount: f32) -> Material {
        Material::Mix(Box::new(MixMaterial {
            names: [a.into(), b.into()],
            names_at: Location::nowhere(),
            indices: [0; 2],
            materials: Vec::new(),
            amount: FloatTexture::Constant(amount),
        }))
    }

    fn hit(i: u32) -> SurfaceInteraction {
        let t = i as f32;
        SurfaceInteraction {
            p: Vec3::new(t.sin(), (1.3 * t).cos(), 0.01 * t),
            wo: Vec3::new((0.7 * t).sin(), 0.5, (0.3 * t).cos()).normalize(),
            ..Default::default()
        }
    }

    /// Amount 0 and 1 always choose the first and the second material; an
    /// amount a chooses the second for a fraction a of the hits, the same
    /// one every time for the same hit.
    #[test]
    fn the_second_material_is_chosen_with_probability_amount() {
        let named: HashMap<&str, u32> = [("a", 0), ("b", 1)].into_iter().collect();
        for amount in [0.0, 0.2, 0.5, 0.9, 1.0] {
            let mut materials = vec![diffuse(0.1), diffuse(0.9), mix("a", "b", amount)];
            resolve(&mut materials, &named).unwrap();
            let Material::Mix(m) = &materials[2] else {
                unreachable!()
            };
            let ctx = TextureEvalContext::default();
            let n = 20_000;
            let second = (0..n)
                .filter(|&i| {
                    let si = hit(i);
                    let chosen = m.choose(&si, &ctx);
                    assert!(std::ptr::eq(chosen, m.choose(&si, &ctx)));
                    std::ptr::eq(chosen, &m.materials()[1])
                })
                .count();
            let fraction = second as f32 / n as f32;
            assert!((fraction - amount).abs() < 0.01, "{amount}: {fraction}");
        }
    }

    /// Mixes within mixes are resolved first; unknown names and cycles are
    /// errors.
    #[test]
    fn nested_mixes_resolve_and_cycles_are_errors() {
        let named: HashMap<&str, u32> = [("a", 0), ("b", 1), ("inner", 2), ("outer", 3)]
            .into_iter()
            .collect();
        let mut materials = vec![
            diffuse(0.1),
            diffuse(0.9),
            mix("a", "b", 0.5),
            mix("inner", "a", 0.5),
        ];
        resolve(&mut materials, &named).unwrap();
        let Material::Mix(outer) = &materials[3] else {
            unreachable!()
        };
        let Material::Mix(inner) = &outer.materials()[0] else {
            panic!("the inner mix was not copied");
        };
        assert_eq!(inner.materials().len(), 2);

        let mut cyclic = vec![
            diffuse(0.1),
            diffuse(0.9),
            mix("a", "outer", 0.5),
            mix("inner", "a", 0.5),
        ];
        let e = resolve(&mut cyclic, &named).unwrap_err().to_string();
        assert!(e.contains("contains itself"), "{e}");
        let mut unknown = vec![diffuse(0.1), diffuse(0.9), mix("a", "nowhere", 0.5)];
        let e = resolve(&mut unknown, &named).unwrap_err().to_string();
        assert!(e.contains("\"nowhere\" is not defined"), "{e}");
    }
}
