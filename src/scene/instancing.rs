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
//! - Motion blur, as pbrt-v4's `AnimatedPrimitive`: an instance whose
//!   transform moves (`ActiveTransform`/`TransformTimes`) is never
//!   flattened, and its render-from-instance is a [`MotionTransform`]. A
//!   moving shape at the top level becomes an object of its own, made in
//!   object space and placed by render-from-object over time. A moving
//!   shape inside an object (a third level) is refused with its location,
//!   and so is a moving area light (pbrt-v4 refuses those too).

use crate::error::{scene_error, Result};
use crate::math::{MotionTransform, Transform};
use crate::scene_description::{AnimatedTransform, SceneDescription, Shape};
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
    /// Made with the identity transform, in its own object space: a
    /// moving shape, which an instance places over time.
    pub in_object_space: bool,
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
    /// of an object used more than once or moving, and one per moving
    /// shape.
    pub instances: Vec<(u32, MotionTransform)>,
}

/// `outer` × the description's transform × `inner`, at both ends of its
/// motion.
fn motion(outer: &Transform, animated: &AnimatedTransform, inner: &Transform) -> MotionTransform {
    let at = |t: &Transform| outer.then(t).then(inner);
    MotionTransform::new(
        at(&animated.start),
        animated.start_time as f32,
        at(animated.end.as_ref().unwrap_or(&animated.start)),
        animated.end_time as f32,
    )
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
    for shape in object_shapes.iter().flatten() {
        if scene.transform(shape.world_from_object).is_animated() {
            return scene_error(
                "a moving shape inside an object (ObjectBegin) is not supported yet (motion blur of instances and of shapes outside objects is)",
                &shape.entity.location.0,
            );
        }
    }
    let shapes = std::mem::take(&mut scene.shapes);
    let animated = |shape: &Shape| scene.transform(shape.world_from_object).is_animated();
    // Most scenes have no moving shape: then the shapes are not copied
    // into a second array (a hair scene's are most of its description).
    let (moving, fixed): (Vec<Shape>, Vec<Shape>) = if shapes.iter().any(animated) {
        shapes.into_iter().partition(animated)
    } else {
        (Vec::new(), shapes)
    };
    let mut placements: Vec<ShapePlacement> = fixed
        .into_iter()
        .map(|shape| ShapePlacement {
            shape,
            flattened_instance: None,
            group: 0,
            in_object_space: false,
        })
        .collect();
    let mut flattened = Vec::new();
    let mut slot = vec![None; scene.objects.len()];
    let mut object_count = 0;
    let mut instances = Vec::new();
    for instance in &scene.instances {
        let render_from_instance = motion(
            render_from_world,
            scene.transform(instance.world_from_instance),
            &world_from_render,
        );
        let start = *render_from_instance.start();
        match uses[instance.object] {
            0 => {}
            1 if !render_from_instance.is_animated() && !start.swaps_handedness() => {
                let index = flattened.len() as u32;
                flattened.push(start);
                let shapes = std::mem::take(&mut object_shapes[instance.object]);
                placements.extend(shapes.into_iter().map(|shape| ShapePlacement {
                    shape,
                    flattened_instance: Some(index),
                    group: 0,
                    in_object_space: false,
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
                    in_object_space: false,
                }),
        );
    }
    // Each moving shape: an object of its own, after the instanced ones.
    for shape in moving {
        if shape.area_light.is_some() {
            return scene_error(
                "a moving area light (motion blur) is not supported (nor by pbrt-v4)",
                &shape.entity.location.0,
            );
        }
        instances.push((
            object_count as u32,
            motion(
                render_from_world,
                scene.transform(shape.world_from_object),
                &Transform::IDENTITY,
            ),
        ));
        object_count += 1;
        placements.push(ShapePlacement {
            shape,
            flattened_instance: None,
            group: object_count as u32,
            in_object_space: true,
        });
    }
    Ok(InstancePlan {
        placements,
        flattened,
        object_count,
        instances,
    })
}
