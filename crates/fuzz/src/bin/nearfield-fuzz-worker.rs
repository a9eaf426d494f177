//! The fuzzing worker: caps its own address space (`NEARFIELD_FUZZ_MEMORY_MB`, default 3072),
//! then answers cases from stdin one line each (see [`nearfield_fuzz::serve`]). An allocation
//! past the cap makes it abort, which the harness reports as a failure of that case.
//! `nearfield-fuzz-worker TARGET FILE` runs one reproducer with the usual panic report.

fn main() {
    // `nearfield-fuzz-worker TARGET FILE`: runs one reproducer in this process with the usual
    // panic report (RUST_BACKTRACE=1 for the stack), and prints its outcome.
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [target, file] = args.as_slice() {
        let target = nearfield_fuzz::Target::from_name(target).unwrap_or_else(|| {
            eprintln!("unknown target '{target}'");
            std::process::exit(2)
        });
        let bytes = std::fs::read(file).expect("read the reproducer");
        let dir = std::env::temp_dir().join(format!("nearfield-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch directory");
        nearfield_fuzz::seeds::prepare(&dir);
        let result = nearfield_fuzz::run_case(target, &bytes, &dir);
        let _ = std::fs::remove_dir_all(&dir);
        println!("{result:?}");
        return;
    }
    let mb: u64 = std::env::var("NEARFIELD_FUZZ_MEMORY_MB")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3072);
    #[cfg(unix)]
    {
        let bytes = mb << 20;
        let limit = libc::rlimit {
            rlim_cur: bytes as libc::rlim_t,
            rlim_max: bytes as libc::rlim_t,
        };
        // SAFETY: setrlimit with a valid struct; no other thread exists yet.
        if unsafe { libc::setrlimit(libc::RLIMIT_AS, &limit) } != 0 {
            eprintln!("nearfield-fuzz-worker: cannot cap memory");
            std::process::exit(1);
        }
    }
    // Panics are answered as failures; their default report would only clutter stderr.
    std::panic::set_hook(Box::new(|_| {}));
    let dir = std::env::temp_dir().join(format!("nearfield-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch directory");
    nearfield_fuzz::seeds::prepare(&dir);
    let result = nearfield_fuzz::serve(
        &mut std::io::stdin().lock(),
        &mut std::io::stdout().lock(),
        &dir,
    );
    let _ = std::fs::remove_dir_all(&dir);
    if let Err(e) = result {
        eprintln!("nearfield-fuzz-worker: {e}");
        std::process::exit(1);
    }
}
