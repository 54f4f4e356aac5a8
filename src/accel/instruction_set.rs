//! The instruction set a scene's ray queries run with, chosen at run time.
//!
//! The shipped build targets baseline x86-64 (SSE2), so that it runs on
//! every x86-64 machine. Nearly every machine that renders today also has
//! x86-64-v3's AVX2, FMA, BMI and LZCNT/POPCNT: where it does, the BVH
//! traversal (inlined with the primitive tests it calls) runs as a second
//! copy compiled for those instructions. The traversal counts and finds set
//! bits for every node it enters, which baseline x86-64 spells out in a
//! dozen instructions each, and the compiler uses the wider registers
//! throughout. Measured: hair renders 6–8 % faster, about what a whole
//! build for x86-64-v3 gains (docs/performance-notes.md).
//!
//! Both copies compute the same thing in the same order: Rust never fuses
//! a multiply and an add on its own, so the images are bit-identical
//! whichever copy runs.

/// Which copy of the ray queries runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InstructionSet {
    /// Compiled for the build's target (baseline x86-64 unless built
    /// otherwise).
    Baseline,
    /// Compiled for x86-64-v3's instructions as well (the features
    /// [`InstructionSet::detect`] checks; the `#[target_feature]` lists of
    /// the copies name the same), chosen only where the processor has
    /// them all.
    X86_64V3,
}

impl InstructionSet {
    /// The best this processor runs.
    pub fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            let v3 = std::is_x86_feature_detected!("avx")
                && std::is_x86_feature_detected!("avx2")
                && std::is_x86_feature_detected!("fma")
                && std::is_x86_feature_detected!("bmi1")
                && std::is_x86_feature_detected!("bmi2")
                && std::is_x86_feature_detected!("lzcnt")
                && std::is_x86_feature_detected!("popcnt")
                && std::is_x86_feature_detected!("sse3")
                && std::is_x86_feature_detected!("ssse3")
                && std::is_x86_feature_detected!("sse4.1")
                && std::is_x86_feature_detected!("sse4.2");
            if v3 {
                return Self::X86_64V3;
            }
        }
        Self::Baseline
    }
}
