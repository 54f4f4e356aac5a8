//! The shapes of every placement (`instancing::plan`), made on all cores:
//! the placements are cut into runs, and each run makes its shapes into
//! its own [`ShapeStorage`]; `build` then appends the runs in file order.
//!
//! A hair scene has one `Shape "curve"` per strand or segment (64,000 in
//! hair-eumel-2-256, each split into 8 pieces), and making them one after
//! another took 140–200 ms of its build. Per run, what its placements
//! share is done once: its arrays are reserved for all its curves' pieces
//! (`reserve_for_curves`), and a transform and its curve facts are
//! reused while the placements keep it (`LastTransform`).

use super::alpha::Alpha;
use super::instancing::ShapePlacement;
use crate::error::{scene_error, Error, Result};
use crate::materials::Material;
use crate::math::Transform;
use crate::media::MediumInterface;
use crate::scene_description::{Entity, MaterialRef, SceneDescription, TransformId};
use crate::shapes::curve::frame::{strand_angle, FibreFrame};
use crate::shapes::curve::CurveTransform;
use crate::shapes::{create_shapes, curve, Shape, ShapeContext, ShapeStorage};
use crate::textures::{FloatTexture, NamedTextures};
use pbrt_parser::{Location as FileLoc, Warning};
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::Path;
use std::sync::mpsc::SyncSender;

/// One placement, its shapes being the next `shape_count` of its run's.
pub struct PlacedShapes<'s> {
    /// The placement's group (`ShapePlacement::group`).
    pub group: usize,
    /// Where its `Shape` directive is (its description is freed once made).
    pub location: FileLoc,
    /// The alpha cutout texture, if any.
    pub alpha: Option<FloatTexture>,
    pub material: u32,
    /// 0 for an invisible shape (alpha 0) unless it emits.
    pub shape_count: usize,
    /// Constant alpha 0: never hit; its shapes (made only for an area
    /// light) emit unseen.
    pub invisible: bool,
    pub area_light: Option<&'s Entity>,
    /// The media on its two sides, where they differ.
    pub medium_interface: Option<MediumInterface>,
}

/// A run of placements' shapes, in file order. `error` is the first
/// placement that failed; `placed` holds those before it.
pub struct Run<'s> {
    pub storage: ShapeStorage,
    pub placed: Vec<PlacedShapes<'s>>,
    /// The placements' shapes, one after another, indexing `storage`.
    /// (One array per run, not one per placement: a hair scene's 600,000
    /// small arrays, allocated as the description was freed, kept most of
    /// its pages from going back to the system.)
    pub shapes: Vec<Shape>,
    pub warnings: Vec<Warning>,
    pub error: Option<Error>,
}

/// What making shapes needs from the rest of the build.
pub struct Context<'a> {
    pub scene: &'a SceneDescription,
    pub render_from_world: &'a Transform,
    pub textures: &'a NamedTextures,
    pub materials: &'a [Material],
    pub named_materials: &'a HashMap<&'a str, u32>,
    /// Media by name.
    pub media: &'a HashMap<&'a str, u16>,
    pub base: &'a Path,
    /// The plan's flattened instances' transforms
    /// (`ShapePlacement::flattened_instance`).
    pub flattened: &'a [Transform],
}

/// Makes the shapes of `placements` in runs, in parallel; the runs come
/// back in order.
///
/// Each run's shape descriptions are dropped as soon as its shapes are
/// made: for a hair scene they are most of the description's memory,
/// which thus shrinks while the shapes grow instead of adding to them.
pub fn create<'s>(placements: Vec<ShapePlacement>, context: &Context<'s>) -> Vec<Run<'s>> {
    // Several runs per thread balance runs whose shapes differ in cost.
    let threads = rayon::current_num_threads();
    let run_length = placements.len().div_ceil(16 * threads).clamp(1, 4096);
    let make_runs = |spent: Option<&SyncSender<Vec<ShapePlacement>>>| -> Vec<Run<'s>> {
        placements
            .into_par_iter()
            .chunks(run_length)
            .map(|run| {
                let out = make_run(&run, context);
                if let Some(spent) = spent {
                    // Where the freeing thread is behind (or gone), the run
                    // is freed here.
                    let _ = spent.try_send(run);
                }
                out
            })
            .collect()
    };
    let runs = if threads > 1 && crate::memory::another_thread_gets_its_own_arena(threads) {
        // The descriptions are freed on a thread of their own, one run
        // after another. Freed on the threads making shapes, they were a
        // third of that work (120 MB curve file: 1.2 million blocks, each
        // allocated by the parser's thread, so every free locked its
        // arena, and the threads freeing waited on each other). At most
        // `FREED_BEHIND` runs wait for it; past that a run frees its own,
        // so a freeing thread left behind (many threads on few cores) does
        // not hold descriptions that would add to the peak.
        std::thread::scope(|scope| {
            let (spent, to_free) =
                std::sync::mpsc::sync_channel::<Vec<ShapePlacement>>(FREED_BEHIND);
            let freeing = std::thread::Builder::new()
                .name("rpbrt-free".into())
                .spawn_scoped(scope, move || to_free.into_iter().for_each(drop));
            // A thread that could not be started: each run frees its own.
            make_runs(freeing.is_ok().then_some(&spent))
        })
    } else {
        make_runs(None)
    };
    // No trim per run: the freed descriptions go back once all runs are
    // made (here). A trim per run (1 ms each, every arena locked
    // meanwhile) once kept 230 MB off the 120 MB curve file's peak; with
    // large blocks mapped on their own (`memory.rs`) the peak is the same
    // without (893 MB, and the hair scenes' at 2 and 16 threads too) and
    // the runs 0.1 s shorter. They go back before the runs are appended,
    // which copies their curve pieces into one array: else the freed
    // pages, the runs and that array are all resident at once (the
    // append's peak, 170 → 122 MB in hair-eumel-2-256).
    crate::memory::return_freed_memory("shapes made");
    runs
}

/// How many runs' descriptions may wait for the freeing thread.
const FREED_BEHIND: usize = 4;

/// The shapes of one run of placements.
fn make_run<'s>(run: &[ShapePlacement], context: &Context<'s>) -> Run<'s> {
    let mut out = Run {
        storage: ShapeStorage::default(),
        placed: Vec::with_capacity(run.len()),
        shapes: Vec::new(),
        warnings: Vec::new(),
        error: None,
    };
    reserve_for_curves(run, &mut out);
    let mut last_transform = LastTransform::default();
    for placement in run {
        let first_shape = out.shapes.len();
        match place(
            placement,
            context,
            &mut out.storage,
            &mut out.warnings,
            &mut out.shapes,
            &mut last_transform,
        ) {
            Ok(placed) => out.placed.push(placed),
            Err(e) => {
                // `shapes` holds the placed shapes' only.
                out.shapes.truncate(first_shape);
                out.error = Some(e);
                break;
            }
        }
    }
    out
}

/// A run's last placement's render-from-object and its curve facts: the
/// next placement most often has the same (a hair file's curves all
/// have), and two matrix products, two determinants and a cube root per
/// curve were a twentieth of making them.
#[derive(Default)]
struct LastTransform {
    /// (in its own object space, its transform, its flattened instance).
    key: Option<(bool, TransformId, Option<u32>)>,
    render_from_object: Transform,
    curve_transform: Option<CurveTransform>,
}

impl LastTransform {
    /// The placement's render-from-object and curve facts.
    fn of(
        &mut self,
        placement: &ShapePlacement,
        context: &Context,
    ) -> (&Transform, CurveTransform) {
        let key = (
            placement.in_object_space,
            placement.shape.world_from_object,
            placement.flattened_instance,
        );
        let curve_transform = match self.curve_transform {
            Some(known) if self.key == Some(key) => known,
            _ => {
                // A moving shape is made in its own space, which its
                // instance moves (`instancing`).
                let mut render_from_object = if placement.in_object_space {
                    Transform::IDENTITY
                } else {
                    context.render_from_world.then(
                        &context
                            .scene
                            .transform(placement.shape.world_from_object)
                            .start,
                    )
                };
                if let Some(instance) = placement.flattened_instance {
                    render_from_object =
                        context.flattened[instance as usize].then(&render_from_object);
                }
                let facts = CurveTransform::of(&render_from_object);
                self.key = Some(key);
                self.render_from_object = render_from_object;
                self.curve_transform = Some(facts);
                facts
            }
        };
        (&self.render_from_object, curve_transform)
    }
}

/// Reserves the run's arrays for the curves of `run`, each piece a
/// shape: grown instead, a doubling at a time, they were copied about once
/// more and their pages touched anew after each run's trim (a tenth of
/// the 120 MB curve file's shapes phase).
fn reserve_for_curves(run: &[ShapePlacement], out: &mut Run) {
    let (mut segments, mut pieces) = (0usize, 0usize);
    for placement in run {
        if matches!(placement.shape.entity.kind.as_str(), "curve" | "bcurve") {
            let (s, p) = curve::expected_counts(&placement.shape.entity.params);
            segments = segments.saturating_add(s);
            pieces = pieces.saturating_add(p);
        }
    }
    // Only a hint: where it cannot be had, the arrays grow as they would.
    let _ = out.storage.curve_segments.try_reserve_exact(segments);
    let _ = out.storage.curve_pieces.try_reserve_exact(pieces);
    let _ = out.shapes.try_reserve_exact(pieces);
}

fn place<'s>(
    placement: &ShapePlacement,
    context: &Context<'s>,
    storage: &mut ShapeStorage,
    warnings: &mut Vec<Warning>,
    run_shapes: &mut Vec<Shape>,
    transforms: &mut LastTransform,
) -> Result<PlacedShapes<'s>> {
    let shape = &placement.shape;
    let mut placed = PlacedShapes {
        group: placement.group as usize,
        location: shape.entity.location.0.clone(),
        alpha: None,
        material: 0,
        shape_count: 0,
        area_light: None,
        invisible: false,
        medium_interface: None,
    };
    let loc = &shape.entity.location.0;
    placed.alpha = match Alpha::create(shape, context.textures, context.base)? {
        // pbrt-v4 keeps an invisible shape's area light: a light reached
        // by light sampling alone.
        Alpha::Invisible if shape.area_light.is_none() => return Ok(placed),
        Alpha::Invisible => {
            placed.invisible = true;
            None
        }
        Alpha::Opaque => None,
        Alpha::Cutout(texture) => Some(texture),
    };
    let inside = context.media.get(shape.inside_medium.as_str()).copied();
    let outside = context.media.get(shape.outside_medium.as_str()).copied();
    placed.medium_interface = (inside != outside).then_some(MediumInterface { inside, outside });
    let (render_from_object, curve_transform) = transforms.of(placement, context);
    placed.material = material_index(&shape.material, context.named_materials, loc)?;
    let material = &context.materials[placed.material as usize];
    // The ring is an outer cylinder around a fibre: on a surface the
    // BSDF would shrink the fibre to the middle of h with no ring around it.
    if material.has_diffracting_ring()
        && !matches!(shape.entity.kind.as_str(), "curve" | "bcurve" | "cyhair")
    {
        return scene_error(
            format!(
                "a hair material with \"d_diff\" > 0 (a diffracting ring around the fibre) needs a curve, not a \"{}\" shape",
                shape.entity.kind
            ),
            loc,
        );
    }
    let shape_context = ShapeContext {
        base_directory: context.base,
        textures: context.textures,
        displacement_edge_scale: context.scene.options.displacement_edge_scale.unwrap_or(1.0)
            as f32,
        curve_transform: Some(curve_transform),
    };
    let first_shape = run_shapes.len();
    create_shapes(
        shape,
        render_from_object,
        shape.reverse_orientation,
        &shape_context,
        storage,
        warnings,
        run_shapes,
    )?;
    let shapes = &run_shapes[first_shape..];
    // The dual hair model's diffracting outer cylinder: the curve is
    // (1 + d_diff) × the fibre's width (issue 5; the BSDF maps the inner
    // 1/(1 + d_diff) of h to the fibre).
    let widening = material.curve_width_scale();
    if widening != 1.0 {
        storage.scale_curve_widths(shapes, widening);
    }
    if let Some(axis) = material.axis_frame() {
        let toward = axis.reference.map(|v| {
            context
                .render_from_world
                .to_mat4()
                .transform_vector3(v)
                .normalize()
        });
        // Strand k of the shape (a `cyhair` shape has one per strand of its
        // file; a `Shape "curve"` only strand 0).
        let frame_of = |strand: usize| match (toward, axis.random) {
            (Some(v), _) => FibreFrame::Toward(v),
            (None, true) => FibreFrame::Turned(strand_angle(loc.offset, strand)),
            (None, false) => FibreFrame::Transported,
        };
        storage.set_fibre_frames(shapes, frame_of);
    }
    placed.area_light = match shape.area_light {
        Some(_) if matches!(material, Material::Interface) => {
            warnings.push(Warning {
                message: "area light on a shape with the \"interface\" material is ignored (as in pbrt-v4)".into(),
                location: loc.clone(),
            });
            None
        }
        Some(_) if matches!(shape.entity.kind.as_str(), "curve" | "bcurve") => return scene_error(
            "curves cannot be area lights: emission from curves is not supported (as in pbrt-v4)",
            loc,
        ),
        Some(a) => Some(&context.scene.area_lights[a as usize]),
        None => None,
    };
    // Every reader of the shape's parameters has run (alpha, the shape).
    shape
        .entity
        .params
        .report_unused(|| format!("shape \"{}\"", shape.entity.kind))?;
    placed.shape_count = shapes.len();
    Ok(placed)
}

/// The index of a shape's material in `BuiltScene::materials`.
fn material_index(
    material: &MaterialRef,
    named: &HashMap<&str, u32>,
    loc: &FileLoc,
) -> Result<u32> {
    match material {
        MaterialRef::Anonymous(i) => Ok(*i),
        MaterialRef::Named(name) => match named.get(name.as_str()) {
            Some(&i) => Ok(i),
            None => scene_error(format!("named material \"{name}\" is not defined"), loc),
        },
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::build::{build, RenderOverrides};
    use std::fmt::Write as _;
    use std::path::Path;

    /// Each curve has its own transform's geometry, width and handedness,
    /// whether the transform is the previous curve's (computed once for
    /// both) or not: curve i, scaled by s = 1, 2 or −1 by turns of three
    /// and some in a flattened instance moved by +100 in z, has its first
    /// point at s·(i, 1, 5) (+ 100 in z), its width 0.1·|s|, and its
    /// normal flipped where s < 0.
    #[test]
    fn curves_sharing_a_transform_or_not_are_placed_by_their_own() {
        let scale = |i: usize| [1.0f32, 2.0, -1.0][(i / 3) % 3];
        let instanced = |i: usize| i % 7 == 0;
        let mut text = String::from("Camera \"perspective\"\nWorldBegin\n");
        let curve = |i: usize| {
            format!(
                "Shape \"curve\" \"point3 P\" [ {i} 1 5 {i}.1 1.1 5 {i}.3 1.1 5 {i}.4 1 5 ] \"float width\" 0.1"
            )
        };
        for i in 0..60 {
            let s = scale(i);
            if instanced(i) {
                writeln!(
                    text,
                    "ObjectBegin \"o{i}\"\nScale {s} {s} {s}\n{}\nObjectEnd",
                    curve(i)
                )
                .unwrap();
                writeln!(
                    text,
                    "AttributeBegin\nTranslate 0 0 100\nObjectInstance \"o{i}\"\nAttributeEnd"
                )
                .unwrap();
            } else {
                writeln!(
                    text,
                    "AttributeBegin\nScale {s} {s} {s}\n{}\nAttributeEnd",
                    curve(i)
                )
                .unwrap();
            }
        }
        let loaded = crate::scene::load_text(Path::new("t.pbrt"), &text).unwrap();
        let scene = build(loaded.scene, &RenderOverrides::default()).unwrap();
        let segments = &scene.shapes.curve_segments;
        assert_eq!(segments.len(), 60);
        let mut seen = [false; 60];
        for segment in segments {
            // Which curve: its first point is s·(i, 1, …).
            let first = segment.cp[0];
            let i = (first.x / first.y).round() as usize;
            assert!(i < 60 && !seen[i], "curve {i} again or unknown: {first}");
            seen[i] = true;
            let s = scale(i);
            let z = 5.0 * s + if instanced(i) { 100.0 } else { 0.0 };
            let expected = glam::Vec3::new(s * i as f32, s, z);
            assert!(
                (first - expected).abs().max_element() < 1e-4,
                "curve {i}: {first}"
            );
            let width = 0.1 * s.abs();
            assert!(
                segment.width.iter().all(|w| (w - width).abs() < 1e-6),
                "curve {i}: {:?}",
                segment.width
            );
            assert_eq!(segment.flip_normal, s < 0.0, "curve {i}");
        }
    }
}
