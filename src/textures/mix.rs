//! The `mix` texture: (1 − amount)·tex1 + amount·tex2.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `tex1` | float/spectrum texture | 0 | the value where `amount` is 0 |
//! | `tex2` | float/spectrum texture | 1 | the value where `amount` is 1 |
//! | `amount` | float texture | 0.5 | the blend |

use super::{FloatTexture, TextureEvalContext, TextureOf, TextureParams};
use crate::error::Result;
use crate::spectrum::color_space::SpectrumKind;

/// A blend of two float or two spectrum textures by a float texture.
#[derive(Clone, Debug)]
pub struct MixTexture<T> {
    pub tex1: Box<T>,
    pub tex2: Box<T>,
    pub amount: Box<FloatTexture>,
}

impl<T: TextureOf> MixTexture<T> {
    pub fn create(tp: &TextureParams, kind: SpectrumKind) -> Result<Self> {
        Ok(MixTexture {
            tex1: Box::new(T::parameter(tp, "tex1", 0.0, kind)?),
            tex2: Box::new(T::parameter(tp, "tex2", 1.0, kind)?),
            amount: Box::new(tp.float_texture("amount", 0.5)?),
        })
    }

    /// The weights of `tex1` and `tex2` at `ctx`.
    pub fn weights(&self, ctx: &TextureEvalContext) -> (f32, f32) {
        let amount = self.amount.evaluate(ctx);
        (1.0 - amount, amount)
    }
}
