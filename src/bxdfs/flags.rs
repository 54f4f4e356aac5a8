//! What kind of scattering a BxDF (or one of its samples) does, and which
//! kinds a caller asks `sample_f`/`pdf` to consider.

use std::ops::{BitAnd, BitOr, BitOrAssign};

/// A set of scattering kinds: on which side light leaves (reflection,
/// transmission) and how spread out the lobe is (diffuse, glossy, specular).
/// Integrators branch on these: specular samples skip MIS and light
/// sampling, non-specular ones get both.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct BxDFFlags(u8);

impl BxDFFlags {
    pub const UNSET: BxDFFlags = BxDFFlags(0);
    pub const REFLECTION: BxDFFlags = BxDFFlags(1 << 0);
    pub const TRANSMISSION: BxDFFlags = BxDFFlags(1 << 1);
    pub const DIFFUSE: BxDFFlags = BxDFFlags(1 << 2);
    pub const GLOSSY: BxDFFlags = BxDFFlags(1 << 3);
    pub const SPECULAR: BxDFFlags = BxDFFlags(1 << 4);
    pub const DIFFUSE_REFLECTION: BxDFFlags = BxDFFlags(1 << 2 | 1 << 0);
    pub const DIFFUSE_TRANSMISSION: BxDFFlags = BxDFFlags(1 << 2 | 1 << 1);
    pub const GLOSSY_REFLECTION: BxDFFlags = BxDFFlags(1 << 3 | 1 << 0);
    pub const GLOSSY_TRANSMISSION: BxDFFlags = BxDFFlags(1 << 3 | 1 << 1);
    pub const SPECULAR_REFLECTION: BxDFFlags = BxDFFlags(1 << 4 | 1 << 0);
    pub const SPECULAR_TRANSMISSION: BxDFFlags = BxDFFlags(1 << 4 | 1 << 1);
    pub const ALL: BxDFFlags = BxDFFlags(0b1_1111);

    pub fn bits(self) -> u8 {
        self.0
    }

    /// Whether every kind in `other` is in `self`.
    pub fn contains(self, other: BxDFFlags) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether `self` and `other` share any kind.
    pub fn intersects(self, other: BxDFFlags) -> bool {
        self.0 & other.0 != 0
    }

    pub fn is_unset(self) -> bool {
        self.0 == 0
    }

    pub fn is_reflective(self) -> bool {
        self.intersects(Self::REFLECTION)
    }

    pub fn is_transmissive(self) -> bool {
        self.intersects(Self::TRANSMISSION)
    }

    pub fn is_diffuse(self) -> bool {
        self.intersects(Self::DIFFUSE)
    }

    pub fn is_glossy(self) -> bool {
        self.intersects(Self::GLOSSY)
    }

    pub fn is_specular(self) -> bool {
        self.intersects(Self::SPECULAR)
    }

    /// Whether some lobe can be evaluated for arbitrary direction pairs
    /// (diffuse or glossy), i.e. light sampling and MIS make sense.
    pub fn is_non_specular(self) -> bool {
        self.intersects(BxDFFlags(Self::DIFFUSE.0 | Self::GLOSSY.0))
    }

    /// Whether any of the hemispheres `sample_flags` asks for is one this
    /// BxDF scatters into (pbrt's `flags & sampleFlags`).
    pub fn allows(self, sample_flags: BxDFReflTransFlags) -> bool {
        (sample_flags.includes_reflection() && self.is_reflective())
            || (sample_flags.includes_transmission() && self.is_transmissive())
    }
}

impl BitOr for BxDFFlags {
    type Output = BxDFFlags;
    fn bitor(self, rhs: BxDFFlags) -> BxDFFlags {
        BxDFFlags(self.0 | rhs.0)
    }
}

impl BitOrAssign for BxDFFlags {
    fn bitor_assign(&mut self, rhs: BxDFFlags) {
        self.0 |= rhs.0;
    }
}

impl BitAnd for BxDFFlags {
    type Output = BxDFFlags;
    fn bitand(self, rhs: BxDFFlags) -> BxDFFlags {
        BxDFFlags(self.0 & rhs.0)
    }
}

/// Which hemispheres a caller wants `sample_f` to draw from and `pdf` to
/// account for. The layered BxDF's random walk asks interfaces for only
/// reflection or only transmission; integrators ask for both.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BxDFReflTransFlags {
    Reflection,
    Transmission,
    #[default]
    All,
}

impl BxDFReflTransFlags {
    pub fn includes_reflection(self) -> bool {
        matches!(self, Self::Reflection | Self::All)
    }

    pub fn includes_transmission(self) -> bool {
        matches!(self, Self::Transmission | Self::All)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn combined_flags_answer_their_queries() {
        let f = BxDFFlags::GLOSSY_REFLECTION | BxDFFlags::SPECULAR_TRANSMISSION;
        assert!(f.is_reflective() && f.is_transmissive());
        assert!(f.is_glossy() && f.is_specular() && !f.is_diffuse());
        assert!(f.is_non_specular());
        assert!(!BxDFFlags::SPECULAR_REFLECTION.is_non_specular());
        assert!(BxDFFlags::UNSET.is_unset());
        assert!(BxDFFlags::ALL.contains(f));
        assert!(!BxDFFlags::DIFFUSE_REFLECTION.allows(BxDFReflTransFlags::Transmission));
        assert!(BxDFFlags::DIFFUSE_REFLECTION.allows(BxDFReflTransFlags::All));
    }
}
