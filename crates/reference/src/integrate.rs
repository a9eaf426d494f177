//! Per-pixel estimators of every AOV (the definitions of docs/src/aovs.md).
//!
//! For the primary hit P (normal n, albedo ρ), N cosine-weighted directions ωᵢ (pdf cos θ/π):
//! - `ao` ≈ mean V_R(ωᵢ);
//! - `env-irradiance` ≈ mean of two samples combined by the balance heuristic: ωᵢ and a
//!   direction drawn from the map's energy (`env_sampling`), each contributing
//!   V_R L_env cos θ/π / (pdf_cos + pdf_env);
//! - `indirect-irradiance` ≈ mean (1 − V_R(ωᵢ)) L_o(x′ᵢ), x′ᵢ the closest hit within R, with
//!   L_o(x′) = Le(x′) + ρ(x′) (E_env(n′)/π + Σ_l E_l(x′, n′)/π), n′ the shading normal of the
//!   side facing P. [`Senders::Physical`] (default, docs/src/aovs.md): the physical direct light
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
use crate::lights::Lights;
use crate::sampling::{Pcg32, cosine_hemisphere, pixel_seed, r2, r2_offset};
use crate::tracer::{Hit, Tracer, offset_origin};
use crate::{PixelResult, ReferenceAov, ReferenceSettings, Senders};
use glam::{Vec2, Vec3};
use nearfield_scene::{Camera, Environment, Scene};
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
    lights: Lights,
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
        Context {
            tracer: Tracer::new(scene),
            scene,
            env,
            camera: *camera,
            settings: *settings,
            irradiance: needs_irradiance.then(|| IrradianceMap::new(env)),
            env_dist: if matches!(
                settings.aov,
                ReferenceAov::EnvIrradiance
                    | ReferenceAov::Diffuse
                    | ReferenceAov::Radiance
                    | ReferenceAov::FarIrradiance
            ) || (settings.aov == ReferenceAov::IndirectIrradiance
                && settings.senders == Senders::Physical)
            {
                EnvDistribution::new(env)
            } else {
                None
            },
            scene_radius: scene.bounds().radius(),
            lights: Lights::new(scene, env),
        }
    }

    /// (1/π) Σ_l E_l(P, n) with shadow rays: exact for punctual lights, the mean of `spp`
    /// stratified directions over each disc light.
    fn light_irradiance(&self, hit: &Hit, x: u32, y: u32, rays: &mut u64) -> (Vec3, Vec3) {
        let eye = self.camera.eye;
        if !self.lights.has_disc {
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

    /// One path-traced estimate of the radiance leaving `hit` towards `from` (the previous path
    /// vertex), emission included, the path having used `segments` segments so far (the one that
    /// reached `hit` included): next-event estimation of the lights and of the environment
    /// (balance heuristic against the cosine-weighted continuation), Russian roulette from the
    /// fourth segment, at most `max_depth` segments in all.
    fn outgoing_radiance(
        &self,
        hit: &Hit,
        from: Vec3,
        segments: u32,
        rng: &mut Pcg32,
        rays: &mut u64,
    ) -> Vec3 {
        let s = &self.settings;
        let mut l = self.scene.emission(hit.material, hit.uv);
        let mut throughput = Vec3::ONE;
        let mut hit = *hit;
        let mut segments = segments;
        let mut from = from;
        while segments < s.max_depth {
            let rho = self.scene.base_color(hit.material, hit.uv).truncate();
            // Next-event estimation: one more segment, to each light (a disc: one direction
            // over it) …
            l += throughput * rho * self.light_irradiance_from(&hit, from, rng.next_vec2(), rays);
            // … and to the environment, drawn from its energy and weighted by the balance
            // heuristic against the cosine-weighted continuation below.
            if let Some(d) = &self.env_dist {
                let (we, pe) = d.sample(self.env, rng.next_vec2());
                let cos = we.dot(hit.ns);
                if pe > 0.0 && cos > 0.0 && we.dot(hit.ng) > 0.0 {
                    *rays += 1;
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
            *rays += 1;
            let o = offset_origin(&hit, w, from, self.scene_radius);
            match self.tracer.closest(o, w, f32::INFINITY, false) {
                None => {
                    l += throughput * self.env.radiance(w) * self.cosine_weight(w, hit.ns);
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
        l
    }

    /// The balance-heuristic weight of a cosine-weighted direction `w` about `n` that reached
    /// the environment, against drawing it from the map's energy (1 without that strategy).
    fn cosine_weight(&self, w: Vec3, n: Vec3) -> f32 {
        match &self.env_dist {
            Some(d) => {
                let pc = w.dot(n).max(0.0) / PI;
                pc / (pc + d.pdf(self.env, w))
            }
            None => 1.0,
        }
    }

    /// `far-irradiance` at the primary hit: (1/π) ∫ V_R L_far cos θ dω. A cosine-weighted
    /// direction that meets nothing within R brings the environment if it escapes (balance
    /// heuristic against a direction drawn from the map's energy, which brings the environment
    /// where nothing at all is in the way) or the path-traced radiance leaving the surface it
    /// meets beyond R; within R it brings nothing.
    fn far_irradiance(&self, x: u32, y: u32, hit: &Hit) -> (Vec3, Vec3, u64) {
        let s = &self.settings;
        let seed = pixel_seed(x, y, s.seed);
        let offset = r2_offset(seed);
        let env_offset = r2_offset(seed ^ 0x6a09_e667);
        let mut rng = Pcg32::new(seed as u64, 0xda3e_39cb_94b9_5bdb);
        let mut stats = Stats::default();
        let mut rays = 0u64;
        let eye = self.camera.eye;
        for i in 0..s.spp {
            let mut e = Vec3::ZERO;
            let w = cosine_hemisphere(hit.ns, r2(i, offset));
            if w.dot(hit.ng) > 0.0 {
                rays += 1;
                let o = offset_origin(hit, w, eye, self.scene_radius);
                match self.tracer.closest(o, w, f32::INFINITY, false) {
                    None => e += self.env.radiance(w) * self.cosine_weight(w, hit.ns),
                    Some(far) if far.t >= s.radius => {
                        e += self.outgoing_radiance(&far, hit.p, 2, &mut rng, &mut rays);
                    }
                    Some(_) => {}
                }
            }
            if let Some(d) = &self.env_dist {
                let (we, pe) = d.sample(self.env, r2(i, env_offset));
                let cos = we.dot(hit.ns);
                if pe > 0.0 && cos > 0.0 && we.dot(hit.ng) > 0.0 {
                    rays += 1;
                    let o = offset_origin(hit, we, eye, self.scene_radius);
                    if !self.tracer.occluded(o, we, f32::INFINITY) {
                        e += self.env.radiance(we) * (cos / PI) / (cos / PI + pe);
                    }
                }
            }
            stats.push(e);
        }
        (stats.mean, stats.stderr(), rays)
    }

    /// [`Lights::irradiance`] at `hit`, shadow rays pushed towards `from`.
    fn light_irradiance_from(&self, hit: &Hit, from: Vec3, u: Vec2, rays: &mut u64) -> Vec3 {
        self.lights
            .irradiance(&self.tracer, self.scene_radius, hit, from, u, rays)
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

    /// `far-irradiance` at pixel (x, y) with the probe volume's radiance in place of the
    /// path-traced one, and the exact visibility: (1/π) ∫ V_R(ω) L_vol(P, ω) cos θ dω from
    /// cosine-weighted directions. It measures the volume alone, without any technique's
    /// estimate of V_R.
    pub fn volume_pixel(
        &self,
        x: u32,
        y: u32,
        volume: &nearfield_scene::probes::ProbeVolume,
    ) -> PixelResult {
        let s = &self.settings;
        let dir = self.camera.primary_ray(x, y, s.size);
        let Some(hit) = self
            .tracer
            .closest(self.camera.eye, dir, f32::INFINITY, true)
        else {
            return PixelResult {
                rays: 1,
                ..Default::default()
            };
        };
        let depth = hit.t * dir.dot(self.camera.forward());
        let sh = volume.sh_at(hit.p, hit.ns, -dir);
        let offset = r2_offset(pixel_seed(x, y, s.seed));
        let mut stats = Stats::default();
        let mut rays = 1u64;
        for i in 0..s.spp {
            let w = cosine_hemisphere(hit.ns, r2(i, offset));
            let mut e = Vec3::ZERO;
            if w.dot(hit.ng) > 0.0 {
                rays += 1;
                let o = offset_origin(&hit, w, self.camera.eye, self.scene_radius);
                if s.radius == 0.0 || !self.tracer.occluded(o, w, s.radius) {
                    e = nearfield_scene::sh::evaluate(&sh, w);
                }
            }
            stats.push(e);
        }
        PixelResult {
            value: stats.mean.max(Vec3::ZERO),
            alpha: 1.0,
            stderr: stats.stderr(),
            depth,
            rays,
        }
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
            ReferenceAov::FarIrradiance => {
                let (e, se, n) = self.far_irradiance(x, y, &hit);
                return done(e, se, rays + n);
            }
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
                    let env_sample = env_terms.then(|| r2(i, env_offset));
                    self.environment(&hit, w, visible, env_sample, &mut rays) + indirect
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

    /// The environment's light at `hit` from the cosine sample `w` (seen within R when
    /// `visible`) and, with `env_sample`, one sample of the environment's own distribution,
    /// combined by the balance heuristic (weights pdf_strategy / (pdf_cos + pdf_env)).
    fn environment(
        &self,
        hit: &Hit,
        w: Vec3,
        visible: bool,
        env_sample: Option<glam::Vec2>,
        rays: &mut u64,
    ) -> Vec3 {
        let radius = self.settings.radius;
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
        if let (Some(u), Some(d)) = (env_sample, &self.env_dist) {
            let (we, pe) = d.sample(self.env, u);
            let cos = we.dot(hit.ns);
            if pe > 0.0 && cos > 0.0 && we.dot(hit.ng) > 0.0 {
                let seen = radius == 0.0 || {
                    *rays += 1;
                    !self.tracer.occluded(
                        offset_origin(hit, we, self.camera.eye, self.scene_radius),
                        we,
                        radius,
                    )
                };
                if seen {
                    env += self.env.radiance(we) * (cos / PI) / (cos / PI + pe);
                }
            }
        }
        env
    }

    fn path_trace(&self, x: u32, y: u32, primary: &Hit, depth: f32) -> PixelResult {
        let s = &self.settings;
        let mut stats = Stats::default();
        let mut rays = 1u64;
        let mut rng = Pcg32::new(pixel_seed(x, y, s.seed) as u64, 0x5851_f42d_4c95_7f2d);
        for _ in 0..s.spp {
            let l = self.outgoing_radiance(primary, self.camera.eye, 1, &mut rng, &mut rays);
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
}
