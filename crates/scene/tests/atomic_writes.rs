//! Every file nearfield writes goes through `nearfield_scene::atomic` (a temporary file renamed
//! over the destination): in the sources of every crate, each call that writes a file names
//! the temporary path (`tmp`) it was given. The fuzzing harness's scratch files are exempt.

#[test]
fn every_writer_writes_a_temporary_file_and_renames_it() {
    let crates = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let writers = [
        "fs::write(",
        ".save(",
        "save_with_format(",
        ".to_file(",
        "File::create(",
    ];
    let mut offenders = Vec::new();
    let mut checked = 0;
    let mut stack = vec![crates.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().flatten() {
            let p = entry.path();
            let rel = p
                .strip_prefix(&crates)
                .unwrap()
                .to_string_lossy()
                .into_owned();
            if p.is_dir() {
                if !rel.starts_with("fuzz") && !rel.ends_with("tests") && !rel.contains("target") {
                    stack.push(p);
                }
                continue;
            }
            if p.extension().is_none_or(|e| e != "rs") || rel.ends_with("atomic.rs") {
                continue;
            }
            let text = std::fs::read_to_string(&p).unwrap();
            // Unit tests at the end of a file write scratch files.
            let code = text.split("#[cfg(test)]").next().unwrap();
            for (n, line) in code.lines().enumerate() {
                if writers.iter().any(|w| line.contains(w)) && !line.trim_start().starts_with("//")
                {
                    checked += 1;
                    if !line.contains("tmp") {
                        offenders.push(format!("{rel}:{}: {}", n + 1, line.trim()));
                    }
                }
            }
        }
    }
    assert!(
        checked >= 5,
        "found only {checked} writers; is the scan looking in the right place?"
    );
    assert!(
        offenders.is_empty(),
        "writes that are not atomic:\n{}",
        offenders.join("\n")
    );
}
