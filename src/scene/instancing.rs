//! Object instancing, pbrt-v4's way: which shapes go to the top level and
//! which into instanced objects, and where each instance is.
//!
//! - An object's shapes are created in render space as they were written
//!   (render-from-world × the transform in force inside `ObjectBegin`); an
//!   instance places them by render-from-instance = render-from-world ×
//!   (the transform at `ObjectInstance`) × world-from-render, as pbrt-v4.
//! - An object used once is flattened: its shapes are created directly with
//!   render-from-instance × render-from-object at the top level (no second
//!   level to traverse) — unless the instance transform swaps handedness:
//!   pbrt-v4 flips normals for a swapping render-from-object transform but
//!   not for a swapping instance transform, so flattening would turn the
//!   normals of its quadrics.
//! - Instances of an object without shapes are skipped with a warning
//!   (pbrt-v4 skips them silently).
//! - Area lights inside objects: the scene builder already warned, as
//!   pbrt-v4 does, and the shapes do not emit.
//! - Animated instance transforms (pbrt-v4 supports them through
//!   `ActiveTransform`/`TransformTimes`) are not supported yet: an error.

use crate::error::{scene_error, Result};
use crate::math::Transform;
use crate::scene_description::{SceneDescription, Shape};
use pbrt_parser::Warning;

/// A shape and where its primitives go. The placement owns the shape's
/// description (taken from the scene description), so that it can be
/// freed as soon as the shape is made.
pub struct ShapePlacement {
    pub shape: Shape,
    /// For a flattened instance: the index in [`InstancePlan::flattened`]
    /// of its render-from-instance, applied after the shape's
    /// render-from-object. (An index, not the transform: a hair scene has
    /// a placement per strand, and 256 bytes each made the plan 170 MB.)
    pub flattened_instance: Option<u32>,
    /// 0: the top level; `k + 1`: instanced object `k`.
    pub group: u32,
}

/// The shapes in group order (top level first, then each instanced object)
/// and the instances.
pub struct InstancePlan {
    pub placements: Vec<ShapePlacement>,
    /// Render-from-instance of each flattened instance (an object used
    /// once), indexed by [`ShapePlacement::flattened_instance`].
    pub flattened: Vec<Transform>,
    /// How many instanced objects (groups `1..=object_count`).
    pub object_count: usize,
    /// (instanced object, render-from-instance), one per `ObjectInstance`
    /// of an object used more than once.
    pub instances: Vec<(u32, Transform)>,
}

/// Plans the scene's shapes and instances, taking every shape out of
/// `scene` into the plan's placements (those of objects never
/// instanced are dropped).
pub fn plan(
    scene: &mut SceneDescription,
    render_from_world: &Transform,
    warnings: &mut Vec<Warning>,
) -> Result<InstancePlan> {
    let world_from_render = render_from_world.inverse();
    let mut uses = vec![0usize; scene.objects.len()];
    let mut warned = vec![false; scene.objects.len()];
    for instance in &scene.instances {
        if scene.transform(instance.world_from_instance).is_animated() {
            return scene_error(
                "animated object instances (ActiveTransform/TransformTimes motion blur) are not supported yet",
                &instance.location.0,
            );
        }
        let object = &scene.objects[instance.object];
        if object.shapes.is_empty() {
            if !std::mem::replace(&mut warned[instance.object], true) {
                warnings.push(Warning {
                    message: format!(
                        "object \"{}\" has no shapes; its instances are skipped",
                        object.name
                    ),
                    location: instance.location.0.clone(),
                });
            }
            continue;
        }
        uses[instance.object] += 1;
    }

    let mut object_shapes: Vec<Vec<Shape>> = scene
        .objects
        .iter_mut()
        .map(|object| std::mem::take(&mut object.shapes))
        .collect();
    let mut placements: Vec<ShapePlacement> = std::mem::take(&mut scene.shapes)
        .into_iter()
        .map(|shape| ShapePlacement {
            shape,
            flattened_instance: None,
            group: 0,
        })
        .collect();
    let mut flattened = Vec::new();
    let mut slot = vec![None; scene.objects.len()];
    let mut object_count = 0;
    let mut instances = Vec::new();
    for instance in &scene.instances {
        let render_from_instance = render_from_world
            .then(&scene.transform(instance.world_from_instance).start)
            .then(&world_from_render);
        match uses[instance.object] {
            0 => {}
            1 if !render_from_instance.swaps_handedness() => {
                let index = flattened.len() as u32;
                flattened.push(render_from_instance);
                let shapes = std::mem::take(&mut object_shapes[instance.object]);
                placements.extend(shapes.into_iter().map(|shape| ShapePlacement {
                    shape,
                    flattened_instance: Some(index),
                    group: 0,
                }))
            }
            _ => {
                let k = *slot[instance.object].get_or_insert_with(|| {
                    object_count += 1;
                    object_count - 1
                });
                instances.push((k as u32, render_from_instance));
            }
        }
    }
    // Instanced objects' shapes, grouped by object.
    let mut by_slot: Vec<(usize, usize)> = slot
        .iter()
        .enumerate()
        .filter_map(|(object, k)| k.map(|k| (k, object)))
        .collect();
    by_slot.sort_unstable();
    for (k, object) in by_slot {
        placements.extend(
            std::mem::take(&mut object_shapes[object])
                .into_iter()
                .map(|shape| ShapePlacement {
                    shape,
                    flattened_instance: None,
                    group: k as u32 + 1,
                }),
        );
    }
    Ok(InstancePlan {
        placements,
        flattened,
        object_count,
        instances,
    })
}
