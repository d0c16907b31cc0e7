//! Drag of an agent relative to full immersion in the bulk liquid.
//!
//! Every drag the model and the plant use — the translational `σ = 3πηd` behind the pair,
//! pull and capillary velocities and the diffusion constant, and the rotational `πηd³` behind
//! the magnet's rotation time — is the bulk value times one of these factors. The medium
//! gives them ([`crate::plant::Medium::drag`]): 1 in the bulk, the interface's fraction at a
//! liquid–air interface.

/// Translational and rotational drag relative to full immersion (1 = bulk liquid).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DragFactors {
    /// Drag against translation in the plane, relative to `3πηd`.
    pub translation: f64,
    /// Drag against rotation about the vertical axis, relative to `πηd³`.
    pub rotation: f64,
}

impl DragFactors {
    /// Full immersion: the bulk Stokes drags.
    pub const BULK: Self = Self {
        translation: 1.0,
        rotation: 1.0,
    };
}

impl Default for DragFactors {
    fn default() -> Self {
        Self::BULK
    }
}
