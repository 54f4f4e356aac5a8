//! `rpbrt mie`: exact scattering of a plane wave by a homogeneous circular
//! cylinder (Lorenz–Mie theory for cylinders; Bohren & Huffman 1983, ch. 8),
//! the wave-optics reference the dual hair model is measured against.
//! (Being written.)

/// Options of `rpbrt mie`.
#[derive(clap::Args, Clone, Debug)]
pub struct MieArgs {}

/// Runs the tool.
pub fn run(_args: &MieArgs) -> Result<(), String> {
    Err("rpbrt mie is not available yet".into())
}
