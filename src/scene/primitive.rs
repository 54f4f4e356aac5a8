//! A primitive: a shape with its material, area light, alpha cutout and
//! media, in 32 bytes.
//!
//! A hair scene has millions of them (4.8 million curve pieces in the
//! 120 MB curve file), so the optional indices are kept in `u32`s with
//! `u32::MAX` for none instead of `Option<u32>` (8 bytes each), and the
//! medium interface in one `u32` of two `u16` media: 48 bytes became 32,
//! 77 MB less at every phase of that file's build.

use crate::media::MediumInterface;
use crate::shapes::Shape;

/// No index (no area light, no cutout, no medium interface).
const NONE: u32 = u32::MAX;

/// The `u16` of a vacuum side in a packed medium interface; media are
/// numbered below it (`create_media` refuses more).
pub const VACUUM: u16 = u16::MAX;

/// A shape with its material and emission.
#[derive(Clone, Debug)]
pub struct Primitive {
    pub shape: Shape,
    /// Index into [`BuiltScene::materials`](super::build::BuiltScene).
    pub material: u32,
    area_light: u32,
    alpha: u32,
    medium_interface: u32,
}

const _: () = assert!(std::mem::size_of::<Primitive>() == 32);

impl Primitive {
    pub fn new(
        shape: Shape,
        material: u32,
        area_light: Option<u32>,
        alpha: Option<u32>,
        medium_interface: Option<MediumInterface>,
    ) -> Primitive {
        let side = |m: Option<u16>| m.unwrap_or(VACUUM) as u32;
        Primitive {
            shape,
            material,
            area_light: area_light.unwrap_or(NONE),
            alpha: alpha.unwrap_or(NONE),
            medium_interface: medium_interface
                .map_or(NONE, |mi| side(mi.inside) | (side(mi.outside) << 16)),
        }
    }

    /// Index into the built scene's lights of its area light.
    pub fn area_light(&self) -> Option<u32> {
        (self.area_light != NONE).then_some(self.area_light)
    }

    /// Index into the built scene's alpha textures of its cutout.
    pub fn alpha(&self) -> Option<u32> {
        (self.alpha != NONE).then_some(self.alpha)
    }

    /// The media on its two sides, where they differ.
    pub fn medium_interface(&self) -> Option<MediumInterface> {
        let side = |m: u32| (m as u16 != VACUUM).then_some(m as u16);
        (self.medium_interface != NONE).then(|| MediumInterface {
            inside: side(self.medium_interface & 0xffff),
            outside: side(self.medium_interface >> 16),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_packed_indices_come_back_as_given() {
        for area_light in [None, Some(0), Some(7), Some(u32::MAX - 1)] {
            for alpha in [None, Some(0), Some(3)] {
                for mi in [
                    None,
                    Some(MediumInterface {
                        inside: Some(0),
                        outside: None,
                    }),
                    Some(MediumInterface {
                        inside: None,
                        outside: Some(65534),
                    }),
                    Some(MediumInterface {
                        inside: Some(2),
                        outside: Some(1),
                    }),
                ] {
                    let p = Primitive::new(Shape::Curve(5), 9, area_light, alpha, mi);
                    assert_eq!(
                        (p.area_light(), p.alpha(), p.medium_interface(), p.material),
                        (area_light, alpha, mi, 9)
                    );
                }
            }
        }
    }
}
