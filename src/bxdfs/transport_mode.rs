//! Which quantity a path carries: it decides whether refraction scales by
//! the relative index of refraction (radiance is compressed into the denser
//! medium; importance is not), which makes BTDFs non-symmetric.

use std::ops::Not;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TransportMode {
    /// Paths traced from the camera, carrying radiance towards it.
    #[default]
    Radiance,
    /// Paths traced from lights, carrying importance towards them.
    Importance,
}

impl TransportMode {
    /// The mode of the adjoint walk (used when a layered BxDF samples
    /// from `wi` towards the inside of the layers).
    pub fn opposite(self) -> TransportMode {
        match self {
            TransportMode::Radiance => TransportMode::Importance,
            TransportMode::Importance => TransportMode::Radiance,
        }
    }
}

impl Not for TransportMode {
    type Output = TransportMode;
    fn not(self) -> TransportMode {
        self.opposite()
    }
}
