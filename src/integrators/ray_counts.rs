//! The rays a path traced, by kind: what the path integrator and the
//! diffraction connection add to, and the pipeline sums per task.

/// Rays traced, by kind (pbrt-v4's `--stats` "regular" and "shadow" ray
/// intersection tests): what a render's time is spent on, so that two
/// renders' times can be compared per ray (a material that lets light go
/// on makes longer paths, not only costlier vertices).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Closest-hit rays: the camera ray and each bounce's.
    pub closest_hit: u64,
    /// Shadow rays towards sampled lights.
    pub shadow: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.closest_hit + self.shadow
    }
}

impl std::ops::AddAssign for RayCounts {
    fn add_assign(&mut self, other: RayCounts) {
        self.closest_hit += other.closest_hit;
        self.shadow += other.shadow;
    }
}
