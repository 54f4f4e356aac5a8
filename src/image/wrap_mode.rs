//! What a texel lookup outside the image returns (pbrt-v4's `WrapMode`).

use crate::math::equal_area::wrap_equal_area_square;
use glam::IVec2;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrapMode {
    /// The image tiles the plane.
    Repeat,
    /// Outside is zero.
    Black,
    /// Outside repeats the nearest edge texel.
    Clamp,
    /// The image is an equal-area octahedral sphere map: crossing an edge
    /// continues on the mirrored part of the same edge (see
    /// [`crate::math::equal_area`]).
    OctahedralSphere,
}

impl WrapMode {
    /// Parses pbrt-v4's `wrap` parameter values.
    pub fn parse(text: &str) -> Option<WrapMode> {
        match text {
            "repeat" => Some(WrapMode::Repeat),
            "black" => Some(WrapMode::Black),
            "clamp" => Some(WrapMode::Clamp),
            "octahedralsphere" => Some(WrapMode::OctahedralSphere),
            _ => None,
        }
    }

    /// The texel inside an image of `resolution` that `p` stands for, or
    /// `None` when the lookup should return zero ([`WrapMode::Black`]).
    /// The result always indexes the image, even for coordinates far
    /// outside (pbrt-v4 assumes they never are).
    #[inline]
    pub fn remap(self, p: IVec2, resolution: IVec2) -> Option<IVec2> {
        // An empty image has no texels; treat it as one so nothing divides
        // by zero (images themselves are never empty).
        let resolution = resolution.max(IVec2::ONE);
        let inside = p.cmpge(IVec2::ZERO).all() && p.cmplt(resolution).all();
        if inside {
            return Some(p);
        }
        let last = resolution - IVec2::ONE;
        match self {
            WrapMode::Repeat => Some(IVec2::new(
                p.x.rem_euclid(resolution.x),
                p.y.rem_euclid(resolution.y),
            )),
            WrapMode::Black => None,
            WrapMode::Clamp => Some(p.clamp(IVec2::ZERO, last)),
            WrapMode::OctahedralSphere => Some(wrap_equal_area_square(p, resolution)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn remaps_like_pbrt() {
        let resolution = IVec2::new(4, 3);
        assert_eq!(
            WrapMode::Repeat.remap(IVec2::new(-1, 3), resolution),
            Some(IVec2::new(3, 0))
        );
        assert_eq!(
            WrapMode::Repeat.remap(IVec2::new(9, -4), resolution),
            Some(IVec2::new(1, 2))
        );
        assert_eq!(
            WrapMode::Clamp.remap(IVec2::new(-5, 7), resolution),
            Some(IVec2::new(0, 2))
        );
        assert_eq!(WrapMode::Black.remap(IVec2::new(4, 0), resolution), None);
        assert_eq!(
            WrapMode::Black.remap(IVec2::new(3, 2), resolution),
            Some(IVec2::new(3, 2))
        );
        assert_eq!(
            WrapMode::OctahedralSphere.remap(IVec2::new(-1, 0), resolution),
            Some(IVec2::new(1, 2))
        );
        // Far outside still gives a valid texel.
        let far = WrapMode::OctahedralSphere.remap(IVec2::new(-100, 55), resolution);
        assert!(far.is_some_and(|p| p.cmpge(IVec2::ZERO).all() && p.cmplt(resolution).all()));
        assert_eq!(
            WrapMode::parse("octahedralsphere"),
            Some(WrapMode::OctahedralSphere)
        );
        assert_eq!(WrapMode::parse("mirror"), None);
    }
}
