//! Fuzzing of every input format nearfield reads, on stable Rust.
//!
//! Each [`Target`] has seeds (small generated files, and real files from `../shared/assets`
//! where they are present) that [`mutate`] changes byte by byte, token by token and — for JSON —
//! field by field. A case runs in a worker process ([`Worker`], the `nearfield-fuzz-worker`
//! binary) whose address space is capped, under a time limit: a panic, a hang past the limit or
//! an allocation past the cap (the worker aborts) is a failure, written out as a reproducer file.
//! Every case is a pure function of `(seed, target, index)`, so a failure reproduces from its
//! index as well as from its file.
//!
//! `tests/fuzz.rs` runs a bounded budget per target in CI (`FUZZ_SECONDS`, default 8 s per
//! target) and every file in `regressions/`; `make fuzz` runs the same for as long as asked.

pub mod mutate;
pub mod seeds;

pub use mutate::mutate;

use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// An input format, as the command line receives it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Target {
    GltfJson,
    Glb,
    Obj,
    Mtl,
    PlyAscii,
    PlyBinary,
    Hdr,
    Exr,
    CameraJson,
    ViewScript,
    MethodSpec,
    SetValues,
}

impl Target {
    pub const ALL: [Target; 12] = [
        Target::GltfJson,
        Target::Glb,
        Target::Obj,
        Target::Mtl,
        Target::PlyAscii,
        Target::PlyBinary,
        Target::Hdr,
        Target::Exr,
        Target::CameraJson,
        Target::ViewScript,
        Target::MethodSpec,
        Target::SetValues,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Target::GltfJson => "gltf",
            Target::Glb => "glb",
            Target::Obj => "obj",
            Target::Mtl => "mtl",
            Target::PlyAscii => "ply-ascii",
            Target::PlyBinary => "ply-binary",
            Target::Hdr => "hdr",
            Target::Exr => "exr",
            Target::CameraJson => "camera-json",
            Target::ViewScript => "view-script",
            Target::MethodSpec => "methods",
            Target::SetValues => "set",
        }
    }

    /// The file extension a reproducer is written with (what the command line would read).
    pub fn extension(self) -> &'static str {
        match self {
            Target::GltfJson => "gltf",
            Target::Glb => "glb",
            Target::Obj => "obj",
            Target::Mtl => "mtl",
            Target::PlyAscii | Target::PlyBinary => "ply",
            Target::Hdr => "hdr",
            Target::Exr => "exr",
            Target::CameraJson => "json",
            Target::ViewScript | Target::MethodSpec | Target::SetValues => "txt",
        }
    }

    pub fn from_name(name: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Whether the format is text (token mutations apply).
    pub fn is_text(self) -> bool {
        !matches!(self, Target::Glb | Target::PlyBinary | Target::Exr)
    }

    fn index(self) -> u8 {
        Target::ALL.iter().position(|&t| t == self).unwrap() as u8
    }
}

/// What one input did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Loaded (or parsed) and accepted.
    Accepted,
    /// Refused with an error message of one line.
    Refused(String),
    /// A failure: a panic, an error of several lines, an abort (an allocation past the cap), or
    /// no answer within the time limit.
    Failed(String),
}

/// Runs one input in this process: what the worker does per case. Files are written into
/// `dir` (the worker's scratch directory, which also holds the companions real seeds refer to).
pub fn run_case(target: Target, bytes: &[u8], dir: &Path) -> Result<(), String> {
    use nearfield_render::TechniqueParams;
    let text = || String::from_utf8_lossy(bytes).into_owned();
    let file = |name: &str| -> Result<PathBuf, String> {
        let p = dir.join(name);
        std::fs::write(&p, bytes).map_err(|e| format!("scratch: {e}"))?;
        Ok(p)
    };
    let scene = |p: PathBuf| {
        nearfield_scene::load_scene(&p)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    match target {
        Target::GltfJson => scene(file("case.gltf")?),
        Target::Glb => scene(file("case.glb")?),
        Target::Obj => scene(file("case.obj")?),
        Target::Mtl => {
            file("fuzz.mtl")?;
            let obj = dir.join("uses-fuzz-mtl.obj");
            std::fs::write(&obj, seeds::OBJ_USING_FUZZ_MTL).map_err(|e| e.to_string())?;
            scene(obj)
        }
        Target::PlyAscii | Target::PlyBinary => scene(file("case.ply")?),
        Target::Hdr => nearfield_scene::Environment::load(&file("case.hdr")?)
            .map(|_| ())
            .map_err(|e| e.to_string()),
        Target::Exr => nearfield_scene::Environment::load(&file("case.exr")?)
            .map(|_| ())
            .map_err(|e| e.to_string()),
        Target::CameraJson => nearfield_scene::CameraFile::parse(&text()).map(|_| ()),
        Target::ViewScript => nearfield_cli::view::script::parse(&text()).map(|_| ()),
        Target::MethodSpec => {
            for spec in text().split(',') {
                nearfield_render::technique::check_spec(spec.trim(), &TechniqueParams::default())
                    .map_err(|e| e.to_string())?;
            }
            Ok(())
        }
        Target::SetValues => {
            // First line the technique, then one KEY=VALUE per line, as `--set` takes them.
            let t = text();
            let mut lines = t.lines();
            let technique = lines.next().unwrap_or("").trim().to_string();
            let mut set = Vec::new();
            for kv in lines {
                let (k, v) = kv
                    .split_once('=')
                    .ok_or_else(|| format!("--set {kv}: expected KEY=VALUE"))?;
                set.push((k.trim().to_string(), v.trim().to_string()));
            }
            let params = TechniqueParams {
                set,
                ..Default::default()
            };
            nearfield_render::technique::check_spec(&technique, &params).map_err(|e| e.to_string())
        }
    }
}

/// The worker process: cases go in on its stdin (target byte, length, bytes), one answer line
/// per case comes back on its stdout.
pub struct Worker {
    child: Child,
    stdin: ChildStdin,
    answers: mpsc::Receiver<String>,
    exe: PathBuf,
    memory_mb: u64,
}

impl Worker {
    /// Starts `exe` (the `nearfield-fuzz-worker` binary) with its address space capped at
    /// `memory_mb` MiB.
    pub fn start(exe: &Path, memory_mb: u64) -> std::io::Result<Worker> {
        let mut child = Command::new(exe)
            .env("NEARFIELD_FUZZ_MEMORY_MB", memory_mb.to_string())
            .env("NEARFIELD_LOG", "off")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()?;
        let stdin = child.stdin.take().unwrap();
        let stdout = child.stdout.take().unwrap();
        let (tx, answers) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        Ok(Worker {
            child,
            stdin,
            answers,
            exe: exe.to_path_buf(),
            memory_mb,
        })
    }

    /// Runs one case; on a failure that kills or stalls the worker, a fresh one is started for
    /// the next case.
    pub fn run(&mut self, target: Target, bytes: &[u8], limit: Duration) -> Outcome {
        self.run_raw(target.index(), bytes, limit)
    }

    /// [`Self::run`] with the target as its protocol byte ([`SELF_TEST`] included).
    pub fn run_raw(&mut self, target: u8, bytes: &[u8], limit: Duration) -> Outcome {
        let mut frame = vec![target];
        frame.extend((bytes.len() as u32).to_le_bytes());
        frame.extend(bytes);
        let sent = self
            .stdin
            .write_all(&frame)
            .and_then(|_| self.stdin.flush());
        let outcome = match sent {
            Err(e) => Outcome::Failed(format!("the worker stopped reading ({e})")),
            Ok(()) => match self.answers.recv_timeout(limit) {
                Ok(line) => parse_answer(&line),
                Err(mpsc::RecvTimeoutError::Timeout) => Outcome::Failed(format!(
                    "no answer within {:.1} s (a hang)",
                    limit.as_secs_f64()
                )),
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    let status = self.child.wait().ok();
                    Outcome::Failed(format!(
                        "the worker died ({}): an abort, such as an allocation past the {} MiB cap",
                        status.map(|s| s.to_string()).unwrap_or_default(),
                        self.memory_mb
                    ))
                }
            },
        };
        if matches!(outcome, Outcome::Failed(_)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
            if let Ok(w) = Worker::start(&self.exe.clone(), self.memory_mb) {
                *self = w;
            }
        }
        outcome
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn parse_answer(line: &str) -> Outcome {
    match line.split_once(' ') {
        Some(("ok", _)) => Outcome::Accepted,
        _ if line == "ok" => Outcome::Accepted,
        Some(("err", msg)) => Outcome::Refused(msg.to_string()),
        Some(("fail", msg)) => Outcome::Failed(msg.to_string()),
        _ => Outcome::Failed(format!("unreadable answer '{line}'")),
    }
}

/// The worker's side of the protocol: reads cases from `input` until it ends, answers on
/// `output`. A panic is caught and answered as a failure; an error message that spans several
/// lines is one too (the command line promises one line).
pub fn serve(input: &mut impl Read, output: &mut impl Write, dir: &Path) -> std::io::Result<()> {
    loop {
        let mut head = [0u8; 5];
        if input.read_exact(&mut head).is_err() {
            return Ok(());
        }
        let len = u32::from_le_bytes(head[1..5].try_into().unwrap()) as usize;
        let mut bytes = vec![0u8; len];
        input.read_exact(&mut bytes)?;
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            match Target::ALL.get(head[0] as usize) {
                Some(&target) => run_case(target, &bytes, dir),
                None => misbehave(&bytes),
            }
        }));
        let answer = match result {
            Ok(Ok(())) => "ok".to_string(),
            Ok(Err(msg)) if msg.contains('\n') => {
                format!(
                    "fail an error of several lines: {}",
                    msg.replace('\n', "\\n")
                )
            }
            Ok(Err(msg)) => format!("err {msg}"),
            Err(payload) => {
                let msg = payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "a panic".into());
                format!("fail panicked: {}", msg.replace('\n', " "))
            }
        };
        writeln!(output, "{answer}")?;
        output.flush()?;
    }
}

/// The worker's self-test (target byte [`SELF_TEST`]): does what it is told — `panic`, `hang`,
/// `alloc` (more than any cap) — so that a test can check that the harness reports each.
fn misbehave(what: &[u8]) -> Result<(), String> {
    match what {
        b"panic" => panic!("told to panic"),
        b"hang" => loop {
            std::thread::sleep(Duration::from_secs(1));
        },
        b"alloc" => {
            let v = vec![1u8; 1 << 40];
            Err(format!("allocated {} bytes", v.len()))
        }
        _ => Err("unknown self-test".into()),
    }
}

/// The target byte of the worker's self-test.
pub const SELF_TEST: u8 = 255;

/// Tally of one fuzzing run of one target.
#[derive(Clone, Debug, Default)]
pub struct Tally {
    pub cases: u64,
    pub accepted: u64,
    pub refused: u64,
    /// (case index, what happened, reproducer file).
    pub failures: Vec<(u64, String, PathBuf)>,
    pub seconds: f64,
}

/// Runs cases `0, 1, 2, …` of `target` from `seed` for `budget`, writing each failure's input
/// to `crashers/` as a reproducer.
pub fn fuzz(
    worker: &mut Worker,
    target: Target,
    seed: u64,
    budget: Duration,
    limit: Duration,
    crashers: &Path,
) -> Tally {
    let seeds = seeds::seeds(target);
    let start = Instant::now();
    let mut tally = Tally::default();
    let mut index = 0u64;
    while start.elapsed() < budget {
        let input = case(target, &seeds, seed, index);
        match worker.run(target, &input, limit) {
            Outcome::Accepted => tally.accepted += 1,
            Outcome::Refused(_) => tally.refused += 1,
            Outcome::Failed(why) => {
                let _ = std::fs::create_dir_all(crashers);
                let file = crashers.join(format!(
                    "{}-seed{seed}-case{index}.{}",
                    target.name(),
                    target.extension()
                ));
                let _ = std::fs::write(&file, &input);
                tally.failures.push((index, why, file));
            }
        }
        tally.cases += 1;
        index += 1;
    }
    tally.seconds = start.elapsed().as_secs_f64();
    tally
}

/// Case `index` of `target` from `seed`: a seed with 1 to 4 stacked mutations; every 16th case
/// is an unchanged seed (so that the seeds themselves are checked).
pub fn case(target: Target, seeds: &[Vec<u8>], seed: u64, index: u64) -> Vec<u8> {
    let mut rng = fastrand::Rng::with_seed(
        seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (target.index() as u64) << 56 ^ index,
    );
    let base = &seeds[rng.usize(..seeds.len())];
    if index.is_multiple_of(16) {
        return base.clone();
    }
    let mut data = base.clone();
    for _ in 0..rng.usize(1..=4) {
        data = mutate(&mut rng, target, &data, seeds);
    }
    data
}
