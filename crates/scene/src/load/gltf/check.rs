//! Structural checks of a glTF document that the `gltf` crate's validation leaves out, and the
//! reading of its buffers and images within [`crate::limits`]. Every error is one line naming
//! the node, accessor, view, buffer or image.

use crate::limits;
use crate::{Light, LightKind};
use glam::{Mat3, Mat4};
use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// "node 3 ('Arm')" or "node 3".
pub fn node_name(node: &::gltf::Node) -> String {
    match node.name() {
        Some(n) if !n.is_empty() => format!("node {} ('{n}')", node.index()),
        _ => format!("node {}", node.index()),
    }
}

/// Whether a node's extras mark it dynamic: `"nearfield": {"dynamic": true}` (its subtree is
/// then left out of the far field's bake). Other extras are the file's own business; a
/// `nearfield` entry of the wrong shape is an error.
pub fn dynamic_extra(node: &::gltf::Node) -> Result<bool, String> {
    let Some(raw) = node.extras() else {
        return Ok(false);
    };
    let bad = |what: &str| format!("{}: extras \"nearfield\" {what}", node_name(node));
    let value: serde_json::Value =
        serde_json::from_str(raw.get()).map_err(|e| bad(&format!("unreadable: {e}")))?;
    let Some(nf) = value.get("nearfield") else {
        return Ok(false);
    };
    let Some(obj) = nf.as_object() else {
        return Err(bad("must be an object, e.g. {\"dynamic\": true}"));
    };
    for key in obj.keys() {
        if key != "dynamic" {
            return Err(bad(&format!(
                "has an unknown key \"{key}\" (known: dynamic)"
            )));
        }
    }
    match obj.get("dynamic") {
        None => Ok(false),
        Some(serde_json::Value::Bool(b)) => Ok(*b),
        Some(other) => Err(bad(&format!(
            "\"dynamic\" must be true or false, not {other}"
        ))),
    }
}

/// A GLB's declared length covers at least its header and lies within the file (the `gltf`
/// crate subtracts before it checks).
pub fn glb_header(bytes: &[u8]) -> Result<(), String> {
    if bytes.len() < 12 || &bytes[..4] != b"glTF" {
        return Ok(());
    }
    let length = u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize;
    if length < 12 || length > bytes.len() {
        return Err(format!(
            "the GLB header declares {length} bytes; the file has {}",
            bytes.len()
        ));
    }
    Ok(())
}

/// What the `gltf` crate's validation assumes before it checks it (it would panic otherwise):
/// primitives' accessors exist; an image has a URI or a buffer view, and a buffer view with a
/// MIME type.
pub fn before_validation(root: &::gltf::json::Root) -> Result<(), String> {
    let accessors = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let indices = prim.attributes.values().chain(prim.indices.as_ref());
            for a in indices {
                if a.value() >= accessors {
                    return Err(format!(
                        "mesh {m} primitive {p} refers to accessor {}, of {accessors}",
                        a.value()
                    ));
                }
            }
        }
    }
    for (i, image) in root.images.iter().enumerate() {
        match (&image.uri, &image.buffer_view) {
            (Some(_), None) => {}
            (None, Some(_)) if image.mime_type.is_some() => {}
            (None, Some(_)) => {
                return Err(format!("image {i}: a buffer view without a mimeType"));
            }
            _ => {
                return Err(format!(
                    "image {i}: needs exactly one of uri and bufferView"
                ));
            }
        }
    }
    Ok(())
}

/// The types of the attributes nearfield reads: POSITION and NORMAL are float VEC3, TEXCOORD_0
/// a VEC2, indices unsigned SCALAR.
pub fn attribute_types(prim: &::gltf::Primitive) -> Result<(), String> {
    use ::gltf::accessor::{DataType as T, Dimensions as D};
    use ::gltf::mesh::Semantic as S;
    for (semantic, a) in prim.attributes() {
        let ok = match semantic {
            S::Positions | S::Normals => a.data_type() == T::F32 && a.dimensions() == D::Vec3,
            S::TexCoords(_) => {
                matches!(a.data_type(), T::F32 | T::U8 | T::U16) && a.dimensions() == D::Vec2
            }
            _ => true,
        };
        if !ok {
            return Err(format!(
                "accessor {} ({:?}) is {:?} {:?}, not a type that attribute takes",
                a.index(),
                semantic,
                a.dimensions(),
                a.data_type()
            ));
        }
    }
    if let Some(a) = prim.indices()
        && !(matches!(a.data_type(), T::U8 | T::U16 | T::U32) && a.dimensions() == D::Scalar)
    {
        return Err(format!(
            "index accessor {} is {:?} {:?}, not an unsigned SCALAR",
            a.index(),
            a.dimensions(),
            a.data_type()
        ));
    }
    Ok(())
}

/// The node graph must be a forest: no node is its own ancestor, none has two parents, and a
/// scene's roots are roots (listed once). Checked before the hierarchy is walked.
pub fn node_tree(doc: &::gltf::Document) -> Result<(), String> {
    let n = doc.nodes().len();
    if n > limits::MAX_NODES {
        return Err(format!(
            "{n} nodes, beyond the limit of {}",
            limits::MAX_NODES
        ));
    }
    let nodes: Vec<::gltf::Node> = doc.nodes().collect();
    const NONE: usize = usize::MAX;
    let mut parent = vec![NONE; n];
    for node in &nodes {
        for child in node.children() {
            let c = child.index();
            if c == node.index() {
                return Err(format!(
                    "the node hierarchy is not a tree: {} is its own child",
                    node_name(node)
                ));
            }
            if parent[c] != NONE {
                return Err(format!(
                    "the node hierarchy is not a tree: {} has two parents, nodes {} and {}",
                    node_name(&child),
                    parent[c],
                    node.index()
                ));
            }
            parent[c] = node.index();
        }
    }
    // 0 unvisited, 1 on the path being walked up, 2 known to reach a root.
    let mut state = vec![0u8; n];
    let mut path = Vec::new();
    for start in 0..n {
        let mut k = start;
        path.clear();
        loop {
            match state[k] {
                2 => break,
                1 => {
                    return Err(format!(
                        "the node hierarchy is not a tree: {} is its own descendant",
                        node_name(&nodes[k])
                    ));
                }
                _ => {
                    state[k] = 1;
                    path.push(k);
                    if parent[k] == NONE {
                        break;
                    }
                    k = parent[k];
                }
            }
        }
        for &p in &path {
            state[p] = 2;
        }
    }
    for scene in doc.scenes() {
        let mut seen = vec![false; n];
        for root in scene.nodes() {
            let r = root.index();
            if parent[r] != NONE {
                return Err(format!(
                    "scene {} lists {} as a root, but it is a child of node {}",
                    scene.index(),
                    node_name(&root),
                    parent[r]
                ));
            }
            if std::mem::replace(&mut seen[r], true) {
                return Err(format!(
                    "scene {} lists {} twice",
                    scene.index(),
                    node_name(&root)
                ));
            }
        }
    }
    Ok(())
}

/// What a URI refers to: bytes inline (`data:`) or a file beside the glTF.
enum Uri {
    Data(Vec<u8>),
    File(PathBuf),
}

fn parse_uri(base: &Path, uri: &str) -> Result<Uri, String> {
    use base64::Engine as _;
    if let Some(rest) = uri.strip_prefix("data:") {
        let payload = match rest.split_once(";base64,") {
            Some((_, b)) => b,
            None => return Err("a data URI that is not base64".into()),
        };
        return base64::engine::general_purpose::STANDARD
            .decode(payload.trim_end())
            .map(Uri::Data)
            .map_err(|e| format!("a data URI that is not valid base64 ({e})"));
    }
    let rel = uri
        .strip_prefix("file://")
        .or_else(|| uri.strip_prefix("file:"))
        .unwrap_or(uri);
    if rel.contains(':') && !uri.starts_with("file:") {
        return Err(format!("unsupported URI scheme in '{}'", short(uri)));
    }
    let decoded = percent_encoding::percent_decode_str(rel)
        .decode_utf8()
        .map_err(|_| format!("URI '{}' is not valid UTF-8 once decoded", short(uri)))?;
    Ok(Uri::File(base.join(&*decoded)))
}

fn short(s: &str) -> Cow<'_, str> {
    if s.len() <= 60 {
        Cow::Borrowed(s)
    } else {
        let cut = (0..=60).rev().find(|&i| s.is_char_boundary(i)).unwrap_or(0);
        Cow::Owned(format!("{}…", &s[..cut]))
    }
}

fn read_file(path: &Path) -> Result<Vec<u8>, String> {
    limits::check_regular_file(path).map_err(|e| e.to_string())?;
    std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// Reads every buffer (the GLB blob, data URIs, files beside the glTF), each at least its
/// declared `byteLength`.
pub fn import_buffers(
    doc: &::gltf::Document,
    base: &Path,
    blob: Option<&[u8]>,
) -> Result<Vec<Vec<u8>>, String> {
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let i = buffer.index();
        let data = match buffer.source() {
            ::gltf::buffer::Source::Bin => blob
                .ok_or_else(|| format!("buffer {i}: refers to a GLB binary chunk there is not"))?
                .to_vec(),
            ::gltf::buffer::Source::Uri(uri) => match parse_uri(base, uri) {
                Ok(Uri::Data(d)) => d,
                Ok(Uri::File(p)) => read_file(&p).map_err(|e| format!("buffer {i}: {e}"))?,
                Err(e) => return Err(format!("buffer {i}: {e}")),
            },
        };
        if data.len() < buffer.length() {
            return Err(format!(
                "buffer {i}: {} bytes, but byteLength is {}",
                data.len(),
                buffer.length()
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// `offset + stride·(count − 1) + size` within `length`, without overflow.
fn fits(offset: usize, stride: usize, count: usize, size: usize, length: usize) -> bool {
    count
        .checked_sub(1)
        .and_then(|c| stride.checked_mul(c))
        .and_then(|x| x.checked_add(offset))
        .and_then(|x| x.checked_add(size))
        .is_some_and(|end| end <= length)
}

fn view_range(view: &::gltf::buffer::View, buffers: &[Vec<u8>]) -> Result<(), String> {
    let len = buffers[view.buffer().index()].len();
    if !fits(view.offset(), 1, view.length().max(1), 1, len) || view.length() == 0 {
        return Err(format!(
            "buffer view {}: bytes {}..{} are outside buffer {} ({len} bytes)",
            view.index(),
            view.offset(),
            view.offset().saturating_add(view.length()),
            view.buffer().index()
        ));
    }
    Ok(())
}

/// Every buffer view lies inside its buffer, and every accessor (sparse parts included) inside
/// its view, with a stride no smaller than an element.
pub fn accessors(doc: &::gltf::Document, buffers: &[Vec<u8>]) -> Result<(), String> {
    for view in doc.views() {
        view_range(&view, buffers)?;
    }
    for a in doc.accessors() {
        let (i, size, count) = (a.index(), a.size(), a.count());
        if count == 0 {
            return Err(format!("accessor {i}: count is 0"));
        }
        if count > limits::MAX_VERTICES.max(3 * limits::MAX_TRIANGLES) {
            return Err(format!("accessor {i}: count {count} is beyond the limit"));
        }
        if let Some(view) = a.view() {
            let stride = view.stride().unwrap_or(size);
            if stride < size {
                return Err(format!(
                    "accessor {i}: buffer view {} has a stride of {stride} bytes, less than an \
                     element ({size} bytes)",
                    view.index()
                ));
            }
            if !fits(a.offset(), stride, count, size, view.length()) {
                return Err(format!(
                    "accessor {i}: {count} elements of {size} bytes (stride {stride}) from \
                     offset {} do not fit in buffer view {} ({} bytes)",
                    a.offset(),
                    view.index(),
                    view.length()
                ));
            }
        }
        if let Some(sparse) = a.sparse() {
            let n = sparse.count();
            if n == 0 || n > count {
                return Err(format!(
                    "accessor {i}: {n} sparse elements for {count} elements"
                ));
            }
            let ix = sparse.indices();
            let isize = ix.index_type().size();
            if !fits(ix.offset(), isize, n, isize, ix.view().length())
                || ix.view().stride().is_some()
            {
                return Err(format!(
                    "accessor {i}: its sparse indices do not fit in buffer view {}",
                    ix.view().index()
                ));
            }
            let vals = sparse.values();
            if !fits(vals.offset(), size, n, size, vals.view().length())
                || vals.view().stride().is_some()
            {
                return Err(format!(
                    "accessor {i}: its sparse values do not fit in buffer view {}",
                    vals.view().index()
                ));
            }
        }
    }
    Ok(())
}

/// The encoded bytes of an image (a buffer view, a data URI or a file).
pub fn image_bytes<'b>(
    image: &::gltf::Image,
    base: &Path,
    buffers: &'b [Vec<u8>],
) -> Result<Cow<'b, [u8]>, String> {
    match image.source() {
        ::gltf::image::Source::View { view, .. } => {
            let data = &buffers[view.buffer().index()];
            // The view's range was checked by `accessors`.
            Ok(Cow::Borrowed(
                &data[view.offset()..view.offset() + view.length()],
            ))
        }
        ::gltf::image::Source::Uri { uri, .. } => match parse_uri(base, uri)? {
            Uri::Data(d) => Ok(Cow::Owned(d)),
            Uri::File(p) => read_file(&p).map(Cow::Owned),
        },
    }
}

/// A node's local and world transforms are finite and within [`limits::MAX_COORDINATE`]; one
/// that carries a mesh, camera or light is not degenerate (zero scale).
pub fn transform(
    node: &::gltf::Node,
    local: &Mat4,
    world: &Mat4,
    carries: bool,
) -> Result<(), String> {
    if !local.to_cols_array().iter().all(|&x| limits::sane(x)) {
        return Err(format!(
            "{} has a non-finite or absurd transform (an entry beyond ±{:e})",
            node_name(node),
            limits::MAX_COORDINATE
        ));
    }
    if !world.to_cols_array().iter().all(|&x| limits::sane(x)) {
        return Err(format!(
            "{}: its world transform overflows (entries beyond ±{:e})",
            node_name(node),
            limits::MAX_COORDINATE
        ));
    }
    if carries {
        let m = Mat3::from_mat4(*world).as_dmat3();
        let scale = m.x_axis.length() * m.y_axis.length() * m.z_axis.length();
        let det = m.determinant().abs();
        if det.is_nan() || det <= 1e-12 * scale || scale == 0.0 {
            return Err(format!(
                "{} has a degenerate (zero-scale) transform",
                node_name(node)
            ));
        }
    }
    Ok(())
}

/// A light's colour, intensity, range and cone angles are finite and meaningful.
pub fn light(l: &Light) -> Result<(), String> {
    if !(l.color.is_finite() && l.color.min_element() >= 0.0) {
        return Err("light colour must be finite and ≥ 0".into());
    }
    if !(l.intensity.is_finite() && l.intensity >= 0.0) {
        return Err(format!(
            "light intensity {} must be finite and ≥ 0",
            l.intensity
        ));
    }
    if let Some(r) = l.range
        && !(r.is_finite() && r > 0.0)
    {
        return Err(format!("light range {r} must be finite and > 0"));
    }
    if let LightKind::Spot {
        inner_cone,
        outer_cone,
        ..
    } = l.kind
        && !(inner_cone >= 0.0
            && inner_cone <= outer_cone
            && outer_cone <= std::f32::consts::FRAC_PI_2)
    {
        return Err(format!(
            "spot cone angles {inner_cone}, {outer_cone} must satisfy 0 ≤ inner ≤ outer ≤ π/2"
        ));
    }
    Ok(())
}
