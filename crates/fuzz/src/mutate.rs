//! Mutations: byte-level (bit flips, interesting bytes and words, insertions, deletions,
//! duplicated and moved ranges, truncation, splicing two seeds), token-level for text (numbers
//! replaced by edge values, lines duplicated or dropped) and structure-aware for JSON (glTF,
//! GLB's JSON chunk, camera files: a field set to an edge value, an index pointed elsewhere, a
//! `children` list that closes a loop, a key removed, an array element duplicated).

use crate::Target;
use fastrand::Rng;
use serde_json::Value;

const INTERESTING_NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "2",
    "3",
    "4",
    "7",
    "16",
    "255",
    "256",
    "65535",
    "65536",
    "2147483647",
    "-2147483648",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "1e20",
    "1e30",
    "1e39",
    "-1e39",
    "3.4e38",
    "1e-45",
    "1e308",
    "0.5",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e999",
    "99999999999",
];

const INTERESTING_U32: &[u32] = &[
    0,
    1,
    2,
    3,
    4,
    0x7f,
    0x80,
    0xff,
    0x100,
    0x7fff,
    0x8000,
    0xffff,
    0x10000,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_fffe,
    0xffff_ffff,
    0x7f80_0000,
    0x7fc0_0000,
    0xff80_0000,
];

/// One mutation of `data` (seeds are the splice partners).
pub fn mutate(rng: &mut Rng, target: Target, data: &[u8], seeds: &[Vec<u8>]) -> Vec<u8> {
    let json = matches!(target, Target::GltfJson | Target::CameraJson);
    let r = rng.u32(0..100);
    if (json || target == Target::Glb) && r < 40 {
        if let Some(out) = mutate_json_structure(rng, target, data) {
            return out;
        }
    }
    if target.is_text() && r < 70 {
        if let Some(out) = mutate_text(rng, data) {
            return out;
        }
    }
    mutate_bytes(rng, data, seeds)
}

fn mutate_bytes(rng: &mut Rng, data: &[u8], seeds: &[Vec<u8>]) -> Vec<u8> {
    let mut d = data.to_vec();
    if d.is_empty() {
        d.push(rng.u8(..));
        return d;
    }
    let n = d.len();
    match rng.u32(0..10) {
        0 => {
            let i = rng.usize(..n);
            d[i] ^= 1 << rng.u32(0..8);
        }
        1 => {
            let i = rng.usize(..n);
            d[i] = rng
                .choice([0u8, 0xff, 0x7f, 0x80, b'0', b'9', b'-', b'.', b'e', b'\n'])
                .unwrap();
        }
        2 => {
            // An interesting little- or big-endian word.
            if n >= 4 {
                let i = rng.usize(..=n - 4);
                let w = *rng.choice(INTERESTING_U32).unwrap();
                let b = if rng.bool() {
                    w.to_le_bytes()
                } else {
                    w.to_be_bytes()
                };
                d[i..i + 4].copy_from_slice(&b);
            }
        }
        3 => {
            let i = rng.usize(..=n);
            let k = rng.usize(1..=16);
            let ins: Vec<u8> = (0..k).map(|_| rng.u8(..)).collect();
            d.splice(i..i, ins);
        }
        4 => {
            let i = rng.usize(..n);
            let k = rng.usize(1..=(n - i).min(64));
            d.drain(i..i + k);
        }
        5 => {
            // Duplicate a range in place.
            let i = rng.usize(..n);
            let k = rng.usize(1..=(n - i).min(256));
            let part = d[i..i + k].to_vec();
            d.splice(i..i, part);
        }
        6 => {
            // Copy a range over another place.
            let i = rng.usize(..n);
            let k = rng.usize(1..=(n - i).min(64));
            let j = rng.usize(..n);
            let part = d[i..i + k].to_vec();
            for (o, b) in part.into_iter().enumerate() {
                if j + o < n {
                    d[j + o] = b;
                }
            }
        }
        7 => d.truncate(rng.usize(..n)),
        8 => {
            // Splice: this one's head, another seed's tail.
            let other = &seeds[rng.usize(..seeds.len())];
            if !other.is_empty() {
                let i = rng.usize(..=n);
                let j = rng.usize(..other.len());
                d.truncate(i);
                d.extend_from_slice(&other[j..]);
            }
        }
        _ => {
            // Several random bytes.
            for _ in 0..rng.usize(2..=8) {
                let i = rng.usize(..n);
                d[i] = rng.u8(..);
            }
        }
    }
    d
}

/// Byte ranges of numbers in text (an optional sign, digits, a fraction, an exponent).
fn number_spans(text: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let c = text[i];
        if c.is_ascii_digit() || (c == b'-' && text.get(i + 1).is_some_and(u8::is_ascii_digit)) {
            let start = i;
            i += 1;
            while i < text.len()
                && (text[i].is_ascii_digit() || matches!(text[i], b'.' | b'e' | b'E' | b'+' | b'-'))
            {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

fn mutate_text(rng: &mut Rng, data: &[u8]) -> Option<Vec<u8>> {
    match rng.u32(0..4) {
        0 | 1 => {
            let spans = number_spans(data);
            let &(a, b) = rng.choice(&spans)?;
            let mut d = data[..a].to_vec();
            d.extend_from_slice(rng.choice(INTERESTING_NUMBERS).unwrap().as_bytes());
            d.extend_from_slice(&data[b..]);
            Some(d)
        }
        2 => {
            // Duplicate a line (many times, sometimes).
            let lines: Vec<&[u8]> = data.split(|&c| c == b'\n').collect();
            let i = rng.usize(..lines.len());
            let times = if rng.u32(0..8) == 0 {
                rng.usize(2..200)
            } else {
                1
            };
            let mut out = Vec::new();
            for (k, l) in lines.iter().enumerate() {
                for _ in 0..(if k == i { times + 1 } else { 1 }) {
                    out.extend_from_slice(l);
                    out.push(b'\n');
                }
            }
            Some(out)
        }
        _ => {
            // Drop a line.
            let lines: Vec<&[u8]> = data.split(|&c| c == b'\n').collect();
            let i = rng.usize(..lines.len());
            let mut out = Vec::new();
            for (k, l) in lines.iter().enumerate() {
                if k != i {
                    out.extend_from_slice(l);
                    out.push(b'\n');
                }
            }
            Some(out)
        }
    }
}

fn mutate_json_structure(rng: &mut Rng, target: Target, data: &[u8]) -> Option<Vec<u8>> {
    if target == Target::Glb {
        let (mut json, bin) = crate::seeds::split_glb(data)?;
        mutate_value(rng, &mut json);
        return Some(crate::seeds::glb(&json, &bin));
    }
    let mut json: Value = serde_json::from_slice(data).ok()?;
    mutate_value(rng, &mut json);
    serde_json::to_vec(&json).ok()
}

/// Every path to a value in `v` (object keys and array indices).
fn paths(v: &Value, prefix: &mut Vec<PathStep>, out: &mut Vec<Vec<PathStep>>) {
    out.push(prefix.clone());
    match v {
        Value::Object(m) => {
            for (k, c) in m {
                prefix.push(PathStep::Key(k.clone()));
                paths(c, prefix, out);
                prefix.pop();
            }
        }
        Value::Array(a) => {
            for (i, c) in a.iter().enumerate() {
                prefix.push(PathStep::Index(i));
                paths(c, prefix, out);
                prefix.pop();
            }
        }
        _ => {}
    }
}

#[derive(Clone)]
enum PathStep {
    Key(String),
    Index(usize),
}

fn at<'a>(v: &'a mut Value, path: &[PathStep]) -> Option<&'a mut Value> {
    let mut cur = v;
    for s in path {
        cur = match s {
            PathStep::Key(k) => cur.get_mut(k)?,
            PathStep::Index(i) => cur.get_mut(*i)?,
        };
    }
    Some(cur)
}

fn mutate_value(rng: &mut Rng, root: &mut Value) {
    let node_count = root
        .get("nodes")
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    // Sometimes: a hierarchy that is not a tree.
    if node_count > 0 && rng.u32(0..6) == 0 {
        let a = rng.usize(..node_count);
        let b = rng.usize(..node_count);
        if let Some(node) = root["nodes"].get_mut(a)
            && let Some(obj) = node.as_object_mut()
        {
            let children = obj
                .entry("children")
                .or_insert_with(|| Value::Array(Vec::new()));
            if let Some(list) = children.as_array_mut() {
                list.push(b.into());
            }
        }
        return;
    }
    let mut all = Vec::new();
    paths(root, &mut Vec::new(), &mut all);
    let path = &all[rng.usize(..all.len())];
    let Some(v) = at(root, path) else { return };
    match v {
        Value::Number(_) | Value::Bool(_) | Value::Null => {
            *v = match rng.u32(0..6) {
                0 => Value::from(rng.i64(-2..8)),
                1 => Value::from(*rng.choice(INTERESTING_U32).unwrap() as u64),
                2 => Value::from(rng.f64() * 1e6 - 5e5),
                3 => serde_json::from_str(
                    rng.choice(["1e30", "-1e30", "1e300", "-0.0", "1.5"])
                        .unwrap(),
                )
                .unwrap(),
                4 => Value::String("x".into()),
                _ => Value::from(-1),
            };
        }
        Value::String(s) => {
            *s = match rng.u32(0..5) {
                0 => String::new(),
                1 => "/dev/zero".into(),
                2 => "%ff%fe".into(),
                3 => "../../../../etc/passwd".into(),
                _ => format!("{s}{s}"),
            };
        }
        Value::Array(a) => match rng.u32(0..4) {
            0 if !a.is_empty() => {
                let i = rng.usize(..a.len());
                let e = a[i].clone();
                a.push(e);
            }
            1 if !a.is_empty() => {
                a.remove(rng.usize(..a.len()));
            }
            2 => a.push(Value::from(rng.i64(-1..(node_count as i64 + 2)))),
            _ => a.clear(),
        },
        Value::Object(m) => {
            if !m.is_empty() && rng.bool() {
                let keys: Vec<String> = m.keys().cloned().collect();
                m.remove(&keys[rng.usize(..keys.len())]);
            } else {
                let key = rng
                    .choice([
                        "children",
                        "mesh",
                        "camera",
                        "matrix",
                        "scale",
                        "sparse",
                        "byteStride",
                        "count",
                        "indices",
                        "uri",
                    ])
                    .unwrap();
                let val = match key {
                    "matrix" => serde_json::json!([0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]),
                    "scale" => serde_json::json!([0, 1e30, -1]),
                    "children" => serde_json::json!([rng.usize(..node_count.max(1))]),
                    "uri" => "/dev/zero".into(),
                    _ => Value::from(rng.i64(-1..5)),
                };
                m.insert(key.into(), val);
            }
        }
    }
}
