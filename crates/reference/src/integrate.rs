//! Per-pixel estimators of every AOV (DESIGN.md's definitions).
//!
//! For the primary hit P (normal n, albedo ρ), N cosine-weighted directions ωᵢ (pdf cos θ/π):
//! - `ao` ≈ mean V_R(ωᵢ);
//! - `env-irradiance` ≈ mean of two samples combined by the balance heuristic: ωᵢ and a
//!   direction drawn from the map's energy (`env_sampling`), each contributing
//!   V_R L_env cos θ/π / (pdf_cos + pdf_env);
//! - `indirect-irradiance` ≈ mean (1 − V_R(ωᵢ)) L_o(x′ᵢ), x′ᵢ the closest hit within R, with
//!   L_o(x′) = Le(x′) + ρ(x′) (E_env(n′)/π + Σ_l E_l(x′, n′)/π), n′ the shading normal of the
//!   side facing P. [`Senders::Physical`] (the default, DESIGN.md): the physical direct light
//!   of x′ — E_env/π estimated at x′ with the full shadow test V_∞ by one cosine-weighted and one
//!   environment-drawn direction (balance heuristic, as at P), and each light with its shadow
//!   ray (a disc light: one direction drawn uniformly over its disc). So `diffuse` at R = ∞ is
//!   the path tracer's `radiance` through the path vertices camera, P, x′ and the light x′ sees
//!   (`max_depth` 3 in our convention, which counts segments: camera → P → x′ → light) minus
//!   P's emission, on scenes whose only emitters are the environment and the lights. [`Senders::Unshadowed`] (analysis only): E_env from
//!   `irradiance::IrradianceMap` and the lights' unshadowed irradiance (V ≡ 1 at x′);
//! - `light-irradiance` = (1/π) Σ_l E_l(P, n) · [shadow ray reaches the light] — exact for
//!   punctual lights; a disc light (the environment's sun, `nearfield_scene::sun`) is sampled
//!   with `spp` directions stratified over its disc, each with its shadow ray;
//! - `diffuse` = ρ (env + light + indirect), R as given;
//! - `radiance`: a path tracer with Lambertian surfaces of albedo ρ, next-event estimation of the
//!   punctual lights and of the environment (drawn from its energy, balance heuristic against the
//!   cosine-weighted continuation, which adds the environment on escape), emission where a path
//!   hits an emitter; `max_depth` segments (camera segment included), Russian roulette from the
//!   fourth segment on. Background pixels show the environment (alpha 0).
//!
//! The standard error is the sample standard deviation over √N (per channel).

use crate::env_sampling::EnvDistribution;
use crate::irradiance::IrradianceMap;
use crate::sampling::{Pcg32, cosine_hemisphere, pixel_seed, r2, r2_offset};
use crate::tracer::{Hit, Tracer, offset_origin};
use crate::{PixelResult, ReferenceAov, ReferenceSettings, Senders};
use glam::{Vec2, Vec3};
use nearfield_scene::{Camera, Environment, Light, LightKind, Scene};
use std::f32::consts::PI;

pub struct Context<'a> {
    pub tracer: Tracer<'a>,
    pub scene: &'a Scene,
    pub env: &'a Environment,
    pub camera: Camera,
    pub settings: ReferenceSettings,
    irradiance: Option<IrradianceMap>,
    env_dist: Option<EnvDistribution>,
    scene_radius: f32,
    /// The scene's lights and the environment's sun (a disc light), if split out.
    lights: Vec<Light>,
    /// Some light is a disc (needs sampling).
    has_disc: bool,
}

/// Running mean and variance (Welford).
#[derive(Default)]
struct Stats {
    n: u32,
    mean: Vec3,
    m2: Vec3,
}

impl Stats {
    fn push(&mut self, x: Vec3) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f32;
        self.m2 += d * (x - self.mean);
    }

    fn stderr(&self) -> Vec3 {
        if self.n < 2 {
            return Vec3::ZERO;
        }
        (self.m2 / ((self.n - 1) as f32 * self.n as f32))
            .max(Vec3::ZERO)
            .map(f32::sqrt)
    }
}

impl<'a> Context<'a> {
    pub fn new(
        scene: &'a Scene,
        env: &'a Environment,
        camera: &Camera,
        settings: &ReferenceSettings,
    ) -> Self {
        let needs_irradiance = settings.senders == Senders::Unshadowed
            && matches!(
                settings.aov,
                ReferenceAov::IndirectIrradiance | ReferenceAov::Diffuse
            );
        let lights: Vec<Light> = scene
            .lights
            .iter()
            .copied()
            .chain(env.sun_light())
            .collect();
        let has_disc = lights.iter().any(|l| disc_radius(l) > 0.0);
        Context {
            tracer: Tracer::new(scene),
            scene,
            env,
            camera: *camera,
            settings: *settings,
            irradiance: needs_irradiance.then(|| IrradianceMap::new(env)),
            env_dist: if matches!(
                settings.aov,
                ReferenceAov::EnvIrradiance | ReferenceAov::Diffuse | ReferenceAov::Radiance
            ) || (settings.aov == ReferenceAov::IndirectIrradiance
                && settings.senders == Senders::Physical)
            {
                EnvDistribution::new(env)
            } else {
                None
            },
            scene_radius: scene.bounds().radius(),
            lights,
            has_disc,
        }
    }

    /// (1/π) Σ_l E_l(P, n) with shadow rays: exact for punctual lights, the mean of `spp`
    /// stratified directions over each disc light.
    fn light_irradiance(&self, hit: &Hit, x: u32, y: u32, rays: &mut u64) -> (Vec3, Vec3) {
        let eye = self.camera.eye;
        if !self.has_disc {
            return (
                self.light_irradiance_from(hit, eye, Vec2::ZERO, rays),
                Vec3::ZERO,
            );
        }
        let offset = r2_offset(pixel_seed(x, y, self.settings.seed) ^ 0xbb67_ae85);
        let mut stats = Stats::default();
        for i in 0..self.settings.spp {
            stats.push(self.light_irradiance_from(hit, eye, r2(i, offset), rays));
        }
        (stats.mean, stats.stderr())
    }

    /// L_o(x′) towards the point `from` it is seen from: emission + ρ (E_env + Σ E_l) / π, with
    /// shadows ([`Senders::Physical`], one estimate from `rng`) or without.
    fn outgoing_diffuse(&self, hit: &Hit, from: Vec3, rng: &mut Pcg32, rays: &mut u64) -> Vec3 {
        let albedo = self.scene.base_color(hit.material, hit.uv).truncate();
        let emission = self.scene.emission(hit.material, hit.uv);
        if self.settings.senders == Senders::Unshadowed {
            let env = self
                .irradiance
                .as_ref()
                .map(|m| m.lookup(hit.ns))
                .unwrap_or(Vec3::ZERO);
            let lights: Vec3 = self
                .lights
                .iter()
                .map(|l| l.irradiance(hit.p, hit.ns))
                .sum::<Vec3>()
                / PI;
            return emission + albedo * (env + lights);
        }
        if albedo.max_element() <= 0.0 {
            return emission;
        }
        let env = self.shadowed_env(hit, from, rng.next_vec2(), rng.next_vec2(), rays);
        let lights = self.light_irradiance_from(hit, from, rng.next_vec2(), rays);
        emission + albedo * (env + lights)
    }

    /// One estimate of (1/π) ∫ L_env V_∞ cos θ dω at `hit`: a cosine-weighted direction (from
    /// `u_cos`) and one drawn from the map's energy (`u_env`), balance heuristic.
    fn shadowed_env(
        &self,
        hit: &Hit,
        from: Vec3,
        u_cos: Vec2,
        u_env: Vec2,
        rays: &mut u64,
    ) -> Vec3 {
        let mut e = Vec3::ZERO;
        let w = cosine_hemisphere(hit.ns, u_cos);
        if w.dot(hit.ng) > 0.0 {
            *rays += 1;
            let o = offset_origin(hit, w, from, self.scene_radius);
            if !self.tracer.occluded(o, w, f32::INFINITY) {
                let weight = match &self.env_dist {
                    Some(d) => {
                        let pc = w.dot(hit.ns).max(0.0) / PI;
                        pc / (pc + d.pdf(self.env, w))
                    }
                    None => 1.0,
                };
                e += self.env.radiance(w) * weight;
            }
        }
        if let Some(d) = &self.env_dist {
            let (we, pe) = d.sample(self.env, u_env);
            let cos = we.dot(hit.ns);
            if pe > 0.0 && cos > 0.0 && we.dot(hit.ng) > 0.0 {
                *rays += 1;
                let o = offset_origin(hit, we, from, self.scene_radius);
                if !self.tracer.occluded(o, we, f32::INFINITY) {
                    e += self.env.radiance(we) * (cos / PI) / (cos / PI + pe);
                }
            }
        }
        e
    }

    pub fn pixel(&self, x: u32, y: u32) -> PixelResult {
        let s = &self.settings;
        let dir = self.camera.primary_ray(x, y, s.size);
        let mut rays = 1u64;
        let Some(hit) = self
            .tracer
            .closest(self.camera.eye, dir, f32::INFINITY, true)
        else {
            let value = if s.aov == ReferenceAov::Radiance {
                self.env.radiance(dir)
            } else {
                Vec3::ZERO
            };
            return PixelResult {
                value,
                rays,
                ..Default::default()
            };
        };
        let depth = hit.t * dir.dot(self.camera.forward());
        let done = |value: Vec3, stderr: Vec3, rays: u64| PixelResult {
            value,
            alpha: 1.0,
            stderr,
            depth,
            rays,
        };
        let albedo = || self.scene.base_color(hit.material, hit.uv).truncate();
        match s.aov {
            ReferenceAov::Albedo => return done(albedo(), Vec3::ZERO, rays),
            ReferenceAov::Normal => return done(hit.ns, Vec3::ZERO, rays),
            ReferenceAov::Depth => return done(Vec3::splat(depth), Vec3::ZERO, rays),
            ReferenceAov::LightIrradiance => {
                let (e, se) = self.light_irradiance(&hit, x, y, &mut rays);
                return done(e, se, rays);
            }
            ReferenceAov::Radiance => return self.path_trace(x, y, &hit, depth),
            _ => {}
        }
        let seed = pixel_seed(x, y, s.seed);
        let offset = r2_offset(seed);
        let env_offset = r2_offset(seed ^ 0x6a09_e667);
        let mut stats = Stats::default();
        let radius = s.radius;
        let needs_hit = matches!(
            s.aov,
            ReferenceAov::IndirectIrradiance | ReferenceAov::Diffuse
        );
        let env_terms = matches!(s.aov, ReferenceAov::EnvIrradiance | ReferenceAov::Diffuse);
        let (rho, (light, light_se)) = if s.aov == ReferenceAov::Diffuse {
            (albedo(), self.light_irradiance(&hit, x, y, &mut rays))
        } else {
            (Vec3::ONE, (Vec3::ZERO, Vec3::ZERO))
        };
        let eye = self.camera.eye;
        // The senders' own estimates (physical senders).
        let mut rng = Pcg32::new(pixel_seed(x, y, s.seed) as u64, 0x9e37_79b9_7f4a_7c15);
        for i in 0..s.spp {
            // Cosine-weighted direction: visibility (ao, env), the near hit (indirect).
            let w = cosine_hemisphere(hit.ns, r2(i, offset));
            let below = w.dot(hit.ng) <= 0.0;
            let (visible, indirect) = if below {
                (false, Vec3::ZERO)
            } else if radius == 0.0 {
                (true, Vec3::ZERO)
            } else if needs_hit {
                rays += 1;
                match self.tracer.closest(
                    offset_origin(&hit, w, eye, self.scene_radius),
                    w,
                    radius,
                    false,
                ) {
                    Some(near) => (
                        false,
                        self.outgoing_diffuse(&near, hit.p, &mut rng, &mut rays),
                    ),
                    None => (true, Vec3::ZERO),
                }
            } else {
                rays += 1;
                (
                    !self.tracer.occluded(
                        offset_origin(&hit, w, eye, self.scene_radius),
                        w,
                        radius,
                    ),
                    Vec3::ZERO,
                )
            };
            let sample = match s.aov {
                ReferenceAov::Ao => Vec3::splat(if visible { 1.0 } else { 0.0 }),
                ReferenceAov::IndirectIrradiance => indirect,
                _ => {
                    // Environment: cosine sample and environment sample combined by the balance
                    // heuristic (weights pdf_strategy / (pdf_cos + pdf_env)).
                    let mut env = Vec3::ZERO;
                    if visible {
                        let weight = match &self.env_dist {
                            Some(d) => {
                                let pc = w.dot(hit.ns).max(0.0) / PI;
                                pc / (pc + d.pdf(self.env, w))
                            }
                            None => 1.0,
                        };
                        env += self.env.radiance(w) * weight;
                    }
                    if let (true, Some(d)) = (env_terms, &self.env_dist) {
                        let (we, pe) = d.sample(self.env, r2(i, env_offset));
                        let cos = we.dot(hit.ns);
                        if pe > 0.0 && cos > 0.0 && we.dot(hit.ng) > 0.0 {
                            let seen = radius == 0.0 || {
                                rays += 1;
                                !self.tracer.occluded(
                                    offset_origin(&hit, we, eye, self.scene_radius),
                                    we,
                                    radius,
                                )
                            };
                            if seen {
                                env += self.env.radiance(we) * (cos / PI) / (cos / PI + pe);
                            }
                        }
                    }
                    env + indirect
                }
            };
            stats.push(sample);
        }
        let (mean, se) = (stats.mean, stats.stderr());
        if s.aov == ReferenceAov::Diffuse {
            // The light's mean comes from its own stratified samples, independent of the
            // hemisphere's: the errors add in quadrature.
            let se = (se * se + light_se * light_se).map(f32::sqrt);
            done(rho * (mean + light), rho * se, rays)
        } else {
            done(mean, se, rays)
        }
    }

    fn path_trace(&self, x: u32, y: u32, primary: &Hit, depth: f32) -> PixelResult {
        let s = &self.settings;
        let mut stats = Stats::default();
        let mut rays = 1u64;
        let mut rng = Pcg32::new(pixel_seed(x, y, s.seed) as u64, 0x5851_f42d_4c95_7f2d);
        for _ in 0..s.spp {
            let mut l = self.scene.emission(primary.material, primary.uv);
            let mut throughput = Vec3::ONE;
            let mut hit = *primary;
            let mut segments = 1;
            let mut from = self.camera.eye;
            while segments < s.max_depth {
                let rho = self.scene.base_color(hit.material, hit.uv).truncate();
                // Next-event estimation: one more segment, to each light (a disc: one direction
                // over it) …
                l += throughput
                    * rho
                    * self.light_irradiance_from(&hit, from, rng.next_vec2(), &mut rays);
                // … and to the environment, drawn from its energy and weighted by the balance
                // heuristic against the cosine-weighted continuation below.
                if let Some(d) = &self.env_dist {
                    let (we, pe) = d.sample(self.env, rng.next_vec2());
                    let cos = we.dot(hit.ns);
                    if pe > 0.0 && cos > 0.0 && we.dot(hit.ng) > 0.0 {
                        rays += 1;
                        let o = offset_origin(&hit, we, from, self.scene_radius);
                        if !self.tracer.occluded(o, we, f32::INFINITY) {
                            let pc = cos / PI;
                            l += throughput * rho * self.env.radiance(we) * (pc / (pc + pe));
                        }
                    }
                }
                let w = cosine_hemisphere(hit.ns, rng.next_vec2());
                if w.dot(hit.ng) <= 0.0 {
                    break;
                }
                throughput *= rho;
                segments += 1;
                rays += 1;
                let o = offset_origin(&hit, w, from, self.scene_radius);
                match self.tracer.closest(o, w, f32::INFINITY, false) {
                    None => {
                        let weight = match &self.env_dist {
                            Some(d) => {
                                let pc = w.dot(hit.ns).max(0.0) / PI;
                                pc / (pc + d.pdf(self.env, w))
                            }
                            None => 1.0,
                        };
                        l += throughput * self.env.radiance(w) * weight;
                        break;
                    }
                    Some(next) => {
                        l += throughput * self.scene.emission(next.material, next.uv);
                        from = hit.p;
                        hit = next;
                    }
                }
                if segments >= 4 {
                    let p = throughput.max_element().min(0.95);
                    if p <= 0.0 || rng.next_f32() >= p {
                        break;
                    }
                    throughput /= p;
                }
            }
            stats.push(l);
        }
        PixelResult {
            value: stats.mean,
            alpha: 1.0,
            stderr: stats.stderr(),
            depth,
            rays,
        }
    }

    /// (1/π) Σ_l E_l at `hit` with shadow rays whose origins are pushed towards `from` (the
    /// camera, or the previous path vertex): exact for punctual lights; a disc light gives one
    /// unbiased sample from `u`, a direction uniform over the disc's solid angle Ω, weighted
    /// L·(ω·n)·Ω = E_n (ω·n) · 2/(1 + cos r) (E_n its normal irradiance, r its radius).
    fn light_irradiance_from(&self, hit: &Hit, from: Vec3, u: Vec2, rays: &mut u64) -> Vec3 {
        let mut e = Vec3::ZERO;
        for light in &self.lights {
            let radius = disc_radius(light);
            if radius > 0.0 {
                let (centre, _) = light.direction_from(hit.p);
                let l = uniform_cone(centre, radius.cos(), u);
                let cos = l.dot(hit.ns);
                if cos <= 0.0 || l.dot(hit.ng) <= 0.0 {
                    continue;
                }
                *rays += 1;
                let o = offset_origin(hit, l, from, self.scene_radius);
                if !self.tracer.occluded(o, l, f32::INFINITY) {
                    e += light.normal_irradiance(hit.p) * (cos * 2.0 / (1.0 + radius.cos()));
                }
                continue;
            }
            let (l, dist) = light.direction_from(hit.p);
            if l.dot(hit.ns) <= 0.0 || l.dot(hit.ng) <= 0.0 {
                continue;
            }
            let irr = light.irradiance(hit.p, hit.ns);
            if irr.max_element() <= 0.0 {
                continue;
            }
            let o = offset_origin(hit, l, from, self.scene_radius);
            let tmax = if dist.is_finite() {
                (hit.p + l * dist - o).length() * (1.0 - 1e-4)
            } else {
                f32::INFINITY
            };
            *rays += 1;
            if !self.tracer.occluded(o, l, tmax) {
                e += irr;
            }
        }
        e / PI
    }
}

/// Angular radius of a disc light (0 for punctual lights).
fn disc_radius(l: &Light) -> f32 {
    match l.kind {
        LightKind::Directional { angular_radius, .. } => angular_radius.max(0.0),
        _ => 0.0,
    }
}

/// A direction uniform over the cone of half-angle acos(`cos_max`) about the unit `axis`.
fn uniform_cone(axis: Vec3, cos_max: f32, u: Vec2) -> Vec3 {
    let cos = 1.0 - u.x * (1.0 - cos_max);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let (t, b) = crate::sampling::orthonormal_basis(axis);
    (t * (sin * phi.cos()) + b * (sin * phi.sin()) + axis * cos).normalize()
}
