//! Options shared by every command: the scene, its environment, the camera, the image size and
//! the adapter (docs/src/cli.md, "Scene options").

use crate::BadInput;
use anyhow::Result;
use clap::Args;
use glam::Vec3;
use nearfield_scene::{Camera, CameraFile, EnvSource, Environment, Scene, SceneSource, SunMode};

#[derive(Args, Clone, Debug)]
pub struct SceneOpts {
    /// Scene: a .gltf/.glb/.obj/.ply file or builtin:NAME (cornell, boxes, city, plane, wall,
    /// closed-box, gap, columns, contact).
    #[arg(default_value = "builtin:cornell")]
    pub scene: String,
    /// Image size in pixels, WIDTHxHEIGHT (each 1..=8192).
    #[arg(long, default_value = "1280x720")]
    pub size: String,
    /// Environment: FILE.hdr, FILE.exr (lat-long), sky, or constant:R,G,B. Default: the scene's
    /// own (sky for files and most built-ins).
    #[arg(long)]
    pub env: Option<String>,
    /// Multiplies the environment's radiance (> 0): the map's values times this are cd/m², as
    /// Bevy's `EnvironmentMapLight::intensity` reads them.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub env_intensity: f32,
    /// Turns the environment about +Y (degrees).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub env_rotation: f32,
    /// Camera: a camera JSON file, or N for the scene's glTF camera N.
    #[arg(long)]
    pub camera: Option<String>,
    /// Camera position x,y,z (m); overrides the camera's.
    #[arg(long, allow_hyphen_values = true)]
    pub eye: Option<String>,
    /// Camera target x,y,z (m); overrides the camera's.
    #[arg(long, allow_hyphen_values = true)]
    pub target: Option<String>,
    /// Vertical field of view (degrees, 0..180); overrides the camera's.
    #[arg(long)]
    pub fov: Option<f32>,
    /// The environment's sun: auto splits a compact bright region (the built-in sky's sun, an
    /// HDR map's sun) into a disc light with shadows and lights with the residual map; off keeps
    /// the map whole.
    #[arg(long, default_value = "auto")]
    pub sun: String,
    /// Use the GPU adapter whose name contains this text (case-insensitive).
    #[arg(long)]
    pub adapter: Option<String>,
    /// Nodes that the far field's bake leaves out, NAME[,NAME…] (glTF node names; a built-in
    /// scene's materials): objects added or moved after the bake, which the frame and the
    /// reference draw (the book, "Near and far").
    #[arg(long, value_delimiter = ',')]
    pub dynamic: Vec<String>,
    /// Adds a model, FILE@X,Y,Z or FILE@X,Y,Z,SCALE (repeatable): the centre of its base at
    /// X,Y,Z (m), scaled by SCALE (default 1); dynamic (the bake leaves it out).
    #[arg(long = "add", value_name = "FILE@X,Y,Z[,SCALE]")]
    pub add: Vec<String>,
}

/// Everything loaded from [`SceneOpts`].
pub struct Loaded {
    pub scene: Scene,
    pub env: Environment,
    pub env_source: EnvSource,
    pub camera: Camera,
    /// What `--sun auto` found, printed once by [`Loaded::report_sun`].
    sun_line: std::cell::Cell<Option<String>>,
}

impl Loaded {
    /// The same environment and camera over another scene.
    pub fn with_scene(&self, scene: Scene) -> Loaded {
        Loaded {
            scene,
            env: self.env.clone(),
            env_source: self.env_source.clone(),
            camera: self.camera,
            sun_line: std::cell::Cell::new(None),
        }
    }

    /// Prints what `--sun auto` found (once, after the command's setup succeeded, so that a
    /// bad input still gets exactly one line).
    pub fn report_sun(&self) {
        if let Some(line) = self.sun_line.take() {
            eprintln!("nearfield: {line}");
        }
    }
}

pub fn parse_size(s: &str) -> Result<(u32, u32)> {
    let bad = || BadInput(format!("--size {s}: expected WIDTHxHEIGHT, e.g. 1280x720"));
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if w == 0 || h == 0 {
        return Err(BadInput(format!("--size {s}: width and height must be at least 1")).into());
    }
    let max = nearfield_render::targets::MAX_SIZE;
    if w > max || h > max {
        return Err(BadInput(format!("--size {s}: the largest side supported is {max}")).into());
    }
    Ok((w, h))
}

fn parse_vec3(flag: &str, s: &str) -> Result<Vec3> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| BadInput(format!("{flag} {s}: expected three numbers x,y,z")))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(BadInput(format!("{flag} {s}: expected three finite numbers x,y,z")).into());
    }
    Ok(Vec3::new(v[0], v[1], v[2]))
}

impl SceneOpts {
    /// Places the `--add` models and marks the `--dynamic` nodes.
    fn add_and_mark(&self, scene: &mut Scene) -> Result<()> {
        for spec in &self.add {
            let (file, place) = spec.rsplit_once('@').ok_or_else(|| {
                BadInput(format!(
                    "--add {spec}: expected FILE@X,Y,Z or FILE@X,Y,Z,SCALE"
                ))
            })?;
            let placement = nearfield_scene::Placement::parse(spec, place)
                .map_err(|e| BadInput(e.to_string()))?;
            let model = SceneSource::parse(file).load()?;
            let name = std::path::Path::new(file)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| file.to_string());
            scene.add(model, &name, placement);
            if scene.triangle_count() > nearfield_scene::limits::MAX_TRIANGLES {
                return Err(BadInput(format!(
                    "--add {spec}: the scene would have more than {} triangles, the limit",
                    nearfield_scene::limits::MAX_TRIANGLES
                ))
                .into());
            }
        }
        let names: Vec<String> = self
            .dynamic
            .iter()
            .map(|n| n.trim().to_string())
            .filter(|n| !n.is_empty())
            .collect();
        scene
            .mark_dynamic(&names)
            .map_err(|e| BadInput(e.to_string()))?;
        Ok(())
    }

    /// Parses and checks the cheap options first (so that a typo fails before a long load), then
    /// loads the scene and environment and resolves the camera.
    pub fn load(&self) -> Result<Loaded> {
        parse_size(&self.size)?;
        if !(self.env_intensity.is_finite() && self.env_intensity > 0.0) {
            return Err(BadInput(format!(
                "--env-intensity {}: must be a finite number > 0",
                self.env_intensity
            ))
            .into());
        }
        if !self.env_rotation.is_finite() {
            return Err(BadInput("--env-rotation: must be finite".into()).into());
        }
        if let Some(f) = self.fov
            && !(f > 0.0 && f < 180.0)
        {
            return Err(BadInput(format!("--fov {f}: must be between 0 and 180 degrees")).into());
        }
        let eye = self
            .eye
            .as_deref()
            .map(|s| parse_vec3("--eye", s))
            .transpose()?;
        let target = self
            .target
            .as_deref()
            .map(|s| parse_vec3("--target", s))
            .transpose()?;
        let env_source = self.env.as_deref().map(EnvSource::parse).transpose()?;
        let sun = SunMode::parse(&self.sun)?;

        let mut scene = SceneSource::parse(&self.scene).load()?;
        self.add_and_mark(&mut scene)?;
        let env_source = env_source.unwrap_or_else(|| scene.default_env.clone());
        let (mut env, found) = env_source.load_split(sun)?;
        env.intensity = self.env_intensity;
        env.rotation = self.env_rotation.to_radians();

        let mut camera = match self.camera.as_deref() {
            None => scene.default_camera(),
            Some(c) => match c.parse::<usize>() {
                Ok(i) => *scene.cameras.get(i).ok_or_else(|| {
                    BadInput(format!(
                        "--camera {i}: the scene has {} camera(s)",
                        scene.cameras.len()
                    ))
                })?,
                Err(_) => CameraFile::load(std::path::Path::new(c))?,
            },
        };
        if let Some(e) = eye {
            camera.eye = e;
        }
        if let Some(t) = target {
            camera.target = t;
        }
        if let Some(f) = self.fov {
            camera.yfov = f.to_radians();
        }
        camera
            .validate()
            .map_err(|e| BadInput(format!("camera: {e}")))?;
        Ok(Loaded {
            scene,
            env,
            env_source,
            camera,
            sun_line: std::cell::Cell::new(found),
        })
    }
}

/// Technique options shared by render and bench.
#[derive(Args, Clone, Debug)]
pub struct TechniqueOpts {
    /// Samples per pixel for sampling techniques (1..=1024); default: the technique's.
    #[arg(long)]
    pub samples: Option<u32>,
    /// Near-field radius in metres (> 0, or inf), or auto (the default): with a probe volume the
    /// distance between its probes, under the sky the technique's own.
    #[arg(long, allow_hyphen_values = true)]
    pub radius: Option<String>,
    /// Technique setting KEY=VALUE (repeatable); see each technique's page in the book (make docs).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Exposure in EV stops applied before tonemapping (−20..=20).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub exposure: f32,
    /// Tonemap operator: aces (Narkowicz' ACES fit), neutral (Khronos PBR Neutral), linear (clamp).
    #[arg(long, default_value = "aces")]
    pub tonemap: String,
    /// Seed of the per-pixel noise sequences.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Shadow-map side in texels (256..=8192).
    #[arg(long, default_value_t = 2048)]
    pub shadow_size: u32,
}

impl TechniqueOpts {
    /// The technique options of a command that measures against the reference at one finite
    /// radius (`fit`, `pareto`): `--radius` (finite), `--set`, `--seed`, defaults elsewhere;
    /// with the parsed parameters and the radius.
    pub fn measured(
        radius: &str,
        set: &[String],
        seed: u32,
    ) -> Result<(Self, nearfield_render::TechniqueParams, f32)> {
        let technique = TechniqueOpts {
            samples: None,
            radius: Some(radius.to_string()),
            set: set.to_vec(),
            exposure: 0.0,
            tonemap: "aces".into(),
            seed,
            shadow_size: 2048,
        };
        let params = technique.params()?;
        let radius = params.radius.expect("given");
        if radius.is_infinite() {
            return Err(BadInput(
                "--radius inf: screen-space techniques need a finite near-field radius".into(),
            )
            .into());
        }
        Ok((technique, params, radius))
    }

    pub fn params(&self) -> Result<nearfield_render::TechniqueParams> {
        if let Some(s) = self.samples
            && !(1..=1024).contains(&s)
        {
            return Err(BadInput(format!("--samples {s}: must be in 1..=1024")).into());
        }
        let radius = match self.radius.as_deref() {
            None | Some("auto") => None,
            Some("inf") => Some(f32::INFINITY),
            Some(r) => {
                let v: f32 = r.parse().map_err(|_| {
                    BadInput(format!("--radius {r}: expected a number, inf or auto"))
                })?;
                if v.is_nan() || v <= 0.0 {
                    return Err(BadInput(format!("--radius {r}: must be > 0 (or inf)")).into());
                }
                Some(v)
            }
        };
        let mut set = Vec::new();
        for kv in &self.set {
            let (k, v) = kv
                .split_once('=')
                .ok_or_else(|| BadInput(format!("--set {kv}: expected KEY=VALUE")))?;
            set.push((k.trim().to_string(), v.trim().to_string()));
        }
        Ok(nearfield_render::TechniqueParams {
            samples: self.samples,
            radius,
            set,
        })
    }

    pub fn settings(&self, size: (u32, u32)) -> Result<nearfield_render::RenderSettings> {
        if !(self.exposure.is_finite() && (-20.0..=20.0).contains(&self.exposure)) {
            return Err(
                BadInput(format!("--exposure {}: must be in −20..=20", self.exposure)).into(),
            );
        }
        let tonemap = nearfield_render::Tonemap::parse(&self.tonemap).ok_or_else(|| {
            BadInput(format!(
                "--tonemap {}: unknown operator (known: {})",
                self.tonemap,
                nearfield_render::Tonemap::NAMES.join(", ")
            ))
        })?;
        if !(256..=8192).contains(&self.shadow_size) {
            return Err(BadInput(format!(
                "--shadow-size {}: must be in 256..=8192",
                self.shadow_size
            ))
            .into());
        }
        let mut s = nearfield_render::RenderSettings {
            size,
            exposure: self.exposure,
            tonemap,
            seed: self.seed,
            ..Default::default()
        };
        s.shadows.size = self.shadow_size;
        Ok(s)
    }
}

/// `--methods M1,M2,...` (default: every registered technique) checked against the registry,
/// and `--frames` checked: shared by `bench` and `compare`.
pub fn methods_and_frames(methods: Option<&str>, frames: u32) -> Result<Vec<String>> {
    let methods: Vec<String> = match methods {
        Some(m) => m.split(',').map(|s| s.trim().to_string()).collect(),
        None => nearfield_render::technique::names()
            .iter()
            .map(|s| s.to_string())
            .collect(),
    };
    for m in &methods {
        nearfield_render::technique::find(m)?;
    }
    if frames == 0 || frames > 100_000 {
        return Err(BadInput(format!("--frames {frames}: must be in 1..=100000")).into());
    }
    Ok(methods)
}

/// `--orbit DEG`: turn per frame, finite and within ±180.
pub fn check_orbit(orbit: f32) -> Result<()> {
    if !(orbit.is_finite() && orbit.abs() <= 180.0) {
        return Err(BadInput(format!(
            "--orbit {orbit}: must be a number of degrees in -180..=180"
        ))
        .into());
    }
    Ok(())
}

/// Camera motion over the frames: `--path FILE` or `--walk` (the book's conventions, "Camera
/// paths"), played at `--fps`.
#[derive(Args, Debug, Clone)]
pub struct MotionOpts {
    /// Camera path: a JSON file of keyframes with times ({"fps": 30, "keyframes": [{"t": 0,
    /// "eye": [x,y,z], "target": [x,y,z], "yfov_deg": 60}, …]}); frame i is the camera at
    /// t₀ + i/fps, and the run renders the path's frames unless --frames says otherwise.
    #[arg(long, conflicts_with = "walk")]
    pub path: Option<std::path::PathBuf>,
    /// The scene's walk from its camera: four seconds stepping a third of the way to the
    /// target while swaying and turning a little (121 frames at 30 fps).
    #[arg(long)]
    pub walk: bool,
    /// Frames per second of --walk, --orbit and a moving scene's clock (a path file states its
    /// own): frame i shows the scene's objects at i / fps seconds.
    #[arg(long, default_value_t = 30.0)]
    pub fps: f32,
}

impl MotionOpts {
    /// Checks the options against `orbit` (`--orbit DEG`, which a path excludes) and reads the
    /// path file: what can be refused before the scene loads.
    pub fn check(&self, orbit: f32) -> Result<Option<nearfield_scene::CameraPath>> {
        check_orbit(orbit)?;
        if !(self.fps.is_finite() && self.fps > 0.0 && self.fps <= 1000.0) {
            let msg = format!("--fps {}: must be a number in (0, 1000]", self.fps);
            return Err(BadInput(msg).into());
        }
        if (self.path.is_some() || self.walk) && orbit != 0.0 {
            let msg = "--orbit: a camera path (--path, --walk) moves the camera already";
            return Err(BadInput(msg.into()).into());
        }
        self.path
            .as_deref()
            .map(|p| {
                nearfield_scene::CameraPath::load(p).map_err(|e| BadInput(e.to_string()).into())
            })
            .transpose()
    }

    /// The motion: the path file read by [`Self::check`], or the scene's walk from `loaded`'s
    /// camera, or `orbit`; with `play`, a still camera over a moving scene stands for its
    /// animation's length. The loaded camera becomes the path's first.
    pub fn motion(
        &self,
        file: Option<nearfield_scene::CameraPath>,
        loaded: &mut Loaded,
        (orbit, play): (f32, bool),
    ) -> Result<Motion> {
        use nearfield_scene::CameraPath;
        let path = match file {
            Some(p) => Some(p),
            None if self.walk => Some(
                CameraPath::walk(loaded.camera, loaded.scene.bounds(), self.fps)
                    .map_err(|e| BadInput(format!("--walk: {e}")))?,
            ),
            None if play && orbit == 0.0 && loaded.scene.moves() => {
                let seconds = loaded.scene.animation.duration();
                Some(CameraPath::standing(loaded.camera, seconds, self.fps).map_err(BadInput)?)
            }
            None => None,
        };
        Ok(match path {
            Some(p) => {
                loaded.camera = p.camera(0);
                Motion::Path(p)
            }
            None => Motion::Orbit {
                degrees: orbit,
                fps: self.fps,
            },
        })
    }
}

/// How the camera moves from frame to frame (turned about its target, or along a path), and the
/// frame rate of the scene's clock.
#[derive(Clone, Debug)]
pub enum Motion {
    /// `--orbit DEG` (0: a still camera) at `--fps`.
    Orbit { degrees: f32, fps: f32 },
    /// `--path`, `--walk`, or a still camera over a moving scene's animation.
    Path(nearfield_scene::CameraPath),
}

impl Motion {
    /// The camera of frame `index` of a run that starts at `start`.
    pub fn camera(&self, start: nearfield_scene::Camera, index: u32) -> nearfield_scene::Camera {
        match *self {
            // Frame 0 (and a still camera) is `start` itself, not a turn by 0° (which rounds).
            Motion::Orbit { degrees, .. } if index == 0 || degrees == 0.0 => start,
            Motion::Orbit { degrees, .. } => start.orbit(degrees * index as f32),
            Motion::Path(ref p) => p.camera(index),
        }
    }

    /// The scene's time at frame `index` (s): `index / fps`.
    pub fn time(&self, index: u32) -> f32 {
        let fps = match self {
            Motion::Orbit { fps, .. } => *fps,
            Motion::Path(p) => p.fps,
        };
        index as f32 / fps
    }

    /// Whether the camera stays where it is.
    pub fn still(&self) -> bool {
        matches!(self, Motion::Orbit { degrees, .. } if *degrees == 0.0)
    }

    /// Renders frame `index`: the scene's objects posed at its time, the camera moved to its
    /// place first (the renderer was made with frame 0's).
    pub fn frame(&self, renderer: &mut nearfield_render::Renderer, index: u32) {
        renderer.set_time(self.time(index));
        match self {
            Motion::Orbit { degrees, .. } => orbit_frame(renderer, index, *degrees),
            Motion::Path(p) => {
                if index > 0 {
                    renderer.set_camera(p.camera(index));
                }
                renderer.render_frame();
            }
        }
    }
}

/// Renders one frame, first turning the camera by `orbit` degrees about its target unless it is
/// the first frame (`index` 0): what `--frames N --orbit DEG` means everywhere.
pub fn orbit_frame(renderer: &mut nearfield_render::Renderer, index: u32, orbit: f32) {
    if index > 0 && orbit != 0.0 {
        let next = renderer.camera().orbit(orbit);
        renderer.set_camera(next);
    }
    renderer.render_frame();
}
