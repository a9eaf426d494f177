//! Arbitrary output variables: what `--aov` can write (the table of docs/src/aovs.md).

/// An output of the frame. `final` is the tonemapped sRGB image (PNG); every other AOV is linear
/// float RGB with alpha 1 on surfaces and 0 on background (EXR).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    /// `radiance` tonemapped and sRGB-encoded.
    Final,
    /// Linear HDR frame: diffuse + specular + emission, environment on background.
    Radiance,
    /// Base colour ρ (factor × texture), linear.
    Albedo,
    /// World-space unit shading normal.
    Normal,
    /// View-space depth along the camera axis (m).
    Depth,
    /// Cosine-weighted near-field visibility, in [0, 1].
    Ao,
    /// (1/π) ∫ L_env V_R cos θ dω.
    EnvIrradiance,
    /// (1/π) Σ E_l with shadows.
    LightIrradiance,
    /// (1/π) ∫ (1 − V_R) L_o cos θ dω.
    IndirectIrradiance,
    /// ρ × (env + light + indirect irradiance).
    Diffuse,
    /// Previous − current pixel position of the surface point (pixels), in r and g.
    Motion,
    /// Specular radiance (lights + prefiltered environment).
    Specular,
    /// Outgoing diffuse radiance kept for the next frame: emission + ρ (light + the far field's
    /// irradiance: the unoccluded sky's SH, or the probe volume's).
    DirectRadiance,
    /// emission + ρ × (env + light + indirect irradiance): the Lambertian part of `radiance`,
    /// the quantity the reference's path tracer (Lambertian surfaces) computes for `radiance`.
    Lambertian,
    /// (1/π) ∫ V_R L_far cos θ dω: what arrives from beyond R. The technique's far-field term —
    /// the same image as `env-irradiance`, whose light is the open sky with `--far sky` and the
    /// probe volume with `--far volume`.
    FarIrradiance,
}

impl Aov {
    /// Every AOV, in the order of their shader ids.
    pub const ALL: [Aov; 15] = [
        Aov::Final,
        Aov::Radiance,
        Aov::Albedo,
        Aov::Normal,
        Aov::Depth,
        Aov::Ao,
        Aov::EnvIrradiance,
        Aov::LightIrradiance,
        Aov::IndirectIrradiance,
        Aov::Diffuse,
        Aov::Motion,
        Aov::Specular,
        Aov::DirectRadiance,
        Aov::Lambertian,
        Aov::FarIrradiance,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Aov::Final => "final",
            Aov::Radiance => "radiance",
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Ao => "ao",
            Aov::EnvIrradiance => "env-irradiance",
            Aov::LightIrradiance => "light-irradiance",
            Aov::IndirectIrradiance => "indirect-irradiance",
            Aov::Diffuse => "diffuse",
            Aov::Motion => "motion",
            Aov::Specular => "specular",
            Aov::DirectRadiance => "direct-radiance",
            Aov::Lambertian => "lambertian",
            Aov::FarIrradiance => "far-irradiance",
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|a| a.name() == s)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|a| a.name()).collect()
    }

    /// The id aov.wgsl switches on.
    pub fn shader_id(self) -> u32 {
        Self::ALL.iter().position(|&a| a == self).unwrap() as u32
    }
}

/// A float AOV image read back from the GPU: RGBA per pixel, row 0 at the top.
#[derive(Clone, Debug)]
pub struct AovImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

impl AovImage {
    pub fn get(&self, x: u32, y: u32) -> [f32; 4] {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Pixels with alpha > 0 (surfaces).
    pub fn surface(&self) -> impl Iterator<Item = &[f32; 4]> {
        self.pixels.iter().filter(|p| p[3] > 0.0)
    }
}
