//! scripts/device-bench.sh times every registered technique (and gtao/hbil with interleaving on
//! and off) at the two sizes it names. CPU only.

#[test]
fn the_device_benchmark_covers_every_technique() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scripts/device-bench.sh");
    let script = std::fs::read_to_string(path).unwrap();
    let methods = script
        .lines()
        .find_map(|l| l.strip_prefix("METHODS="))
        .expect("METHODS= line");
    let listed: Vec<&str> = methods.split(',').collect();
    for name in nearfield_render::technique::names() {
        assert!(
            listed.contains(&name),
            "device-bench.sh does not time {name}"
        );
    }
    for spec in ["gtao:interleaved=off", "hbil:interleaved=off"] {
        assert!(
            listed.contains(&spec),
            "device-bench.sh does not time {spec}"
        );
    }
    for spec in &listed {
        nearfield_render::technique::find(spec).unwrap();
    }
    assert!(script.contains("1280x720 1920x1080"), "sizes");
}
