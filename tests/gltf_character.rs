//! Skinned glTF characters: the two bundled assets, an independent
//! matrix-palette check of CesiumMan's skinning, and small generated files for
//! error paths and every influence/keyframe format.

mod common;
use common::Scratch;
use common::gltf_builder::Builder;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use cornertree::character::{ChannelValues, Character, Interpolation, PoseBuffers, SkinningModel};
use cornertree::io::{AttachedMesh, LoadError, load_character};
use nalgebra::{Matrix4, Quaternion, UnitQuaternion, Vector3};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
}

fn summary(c: &Character) -> String {
    let clips: Vec<String> = c
        .clips
        .iter()
        .map(|k| {
            format!(
                "{:?} {:.4}s ({} channels)",
                k.name,
                k.duration(),
                k.channels.len()
            )
        })
        .collect();
    format!(
        "{}: {} joints, {} vertices, {} triangles, clips: {}",
        c.name,
        c.skeleton.len(),
        c.mesh.vertex_count(),
        c.mesh.triangle_count(),
        clips.join(", ")
    )
}

#[test]
fn cesium_man_loads() {
    let (c, report) = load_character(&asset("CesiumMan.glb")).expect("CesiumMan.glb loads");
    eprintln!("{}", summary(&c));
    eprintln!("notes: {:?}", report.notes);
    assert_eq!(c.skeleton.len(), 19);
    assert_eq!(c.mesh.triangle_count(), 4_672);
    assert_eq!(c.mesh.vertex_count(), 3_273);
    assert_eq!(c.influences.len(), 3_273);
    assert_eq!(c.clips.len(), 1);
    assert_eq!(c.clips[0].name, "animation 0");
    assert!(c.clips[0].duration() > 0.0);
    assert_eq!(c.clips[0].channels.len(), 57);
    assert!(report.skipped_channels.is_empty());
    assert!(report.unskinned_meshes.is_empty());
    assert_eq!(report.skinned_instances, 1);
    assert_eq!(report.skins, [0]);
    assert!(report.attached_meshes.is_empty());
    assert_eq!((report.moved_vertices, report.added_joint_slots), (0, 0));
    for (i, j) in c.skeleton.joints().iter().enumerate() {
        assert!(j.parent.is_none_or(|p| p.index() < i));
    }
}

#[test]
fn brain_stem_loads() {
    let (c, report) = load_character(&asset("BrainStem.glb")).expect("BrainStem.glb loads");
    eprintln!("{}", summary(&c));
    eprintln!(
        "skipped channels: {:?}",
        report
            .skipped_channels
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
    );
    assert_eq!(c.skeleton.len(), 18);
    assert_eq!(c.mesh.triangle_count(), 61_666);
    assert_eq!(c.mesh.vertex_count(), 34_239);
    assert_eq!(report.primitives, 59);
    assert!(!c.clips.is_empty());
    assert!(c.clips[0].duration() > 0.0);
    // Node 2, above the skeleton, carries three constant channels.
    assert_eq!(report.skipped_channels.len(), 3);
    assert!(report.skipped_channels.iter().all(|s| s.node == 2));
    // The base is node 2's world transform, not the identity.
    assert!((c.skeleton.base() - Matrix4::identity()).abs().max() > 0.1);
}

// ---------------------------------------------------------------------------
// Independent matrix-palette skinning of CesiumMan.

/// Linear interpolation of keyframed vectors, clamped at both ends.
fn sample_vec(times: &[f32], values: &[[f32; 3]], t: f32) -> Vector3<f64> {
    let v = |i: usize| {
        Vector3::new(
            values[i][0] as f64,
            values[i][1] as f64,
            values[i][2] as f64,
        )
    };
    let (k, s) = segment(times, t);
    match s {
        None => v(k),
        Some(s) => v(k) * (1.0 - s) + v(k + 1) * s,
    }
}

/// Slerp of keyframed quaternions `[x, y, z, w]`, shortest path, clamped.
fn sample_quat(times: &[f32], values: &[[f32; 4]], t: f32) -> [f64; 4] {
    let q = |i: usize| values[i].map(|c| c as f64);
    let norm = |a: [f64; 4]| {
        let n = a.iter().map(|c| c * c).sum::<f64>().sqrt();
        a.map(|c| c / n)
    };
    let (k, s) = segment(times, t);
    let Some(s) = s else { return norm(q(k)) };
    let a = norm(q(k));
    let mut b = norm(q(k + 1));
    let mut dot: f64 = (0..4).map(|i| a[i] * b[i]).sum();
    if dot < 0.0 {
        b = b.map(|c| -c);
        dot = -dot;
    }
    let (wa, wb) = if dot > 0.9999 {
        (1.0 - s, s)
    } else {
        let theta = dot.acos();
        (
            ((1.0 - s) * theta).sin() / theta.sin(),
            (s * theta).sin() / theta.sin(),
        )
    };
    norm(std::array::from_fn(|i| wa * a[i] + wb * b[i]))
}

fn segment(times: &[f32], t: f32) -> (usize, Option<f64>) {
    if t <= times[0] {
        return (0, None);
    }
    let last = times.len() - 1;
    if t >= times[last] {
        return (last, None);
    }
    let mut k = 0;
    while times[k + 1] <= t {
        k += 1;
    }
    let s = (t as f64 - times[k] as f64) / (times[k + 1] as f64 - times[k] as f64);
    (k, Some(s))
}

fn trs_matrix(t: Vector3<f64>, q: [f64; 4], s: Vector3<f64>) -> Matrix4<f64> {
    let r = UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2]));
    Matrix4::new_translation(&t) * r.to_homogeneous() * Matrix4::new_nonuniform_scaling(&s)
}

/// Skinned world positions of CesiumMan at `t`, straight from the file.
fn reference_skinning(path: &Path, t: f32) -> Vec<[f64; 3]> {
    let gltf = gltf::Gltf::open(path).unwrap();
    let doc = gltf.document;
    let buffers = gltf::import_buffers(&doc, path.parent(), gltf.blob).unwrap();
    let get = |b: gltf::Buffer| Some(buffers[b.index()].0.as_slice());

    // Animated local TRS overrides.
    let anim = doc.animations().next().unwrap();
    let mut translation: HashMap<usize, Vector3<f64>> = HashMap::new();
    let mut rotation: HashMap<usize, [f64; 4]> = HashMap::new();
    let mut scale: HashMap<usize, Vector3<f64>> = HashMap::new();
    for ch in anim.channels() {
        assert_eq!(
            ch.sampler().interpolation(),
            gltf::animation::Interpolation::Linear
        );
        let r = ch.reader(get);
        let times: Vec<f32> = r.read_inputs().unwrap().collect();
        let node = ch.target().node().index();
        match r.read_outputs().unwrap() {
            gltf::animation::util::ReadOutputs::Translations(v) => {
                translation.insert(node, sample_vec(&times, &v.collect::<Vec<_>>(), t));
            }
            gltf::animation::util::ReadOutputs::Scales(v) => {
                scale.insert(node, sample_vec(&times, &v.collect::<Vec<_>>(), t));
            }
            gltf::animation::util::ReadOutputs::Rotations(v) => {
                rotation.insert(
                    node,
                    sample_quat(&times, &v.into_f32().collect::<Vec<_>>(), t),
                );
            }
            _ => panic!("unexpected morph channel"),
        }
    }

    // Node parents and globals by walking up.
    let mut parent = vec![None; doc.nodes().len()];
    for n in doc.nodes() {
        for c in n.children() {
            parent[c.index()] = Some(n.index());
        }
    }
    let nodes: Vec<gltf::Node> = doc.nodes().collect();
    let local = |i: usize| -> Matrix4<f64> {
        let n = &nodes[i];
        let animated =
            translation.contains_key(&i) || rotation.contains_key(&i) || scale.contains_key(&i);
        if !animated {
            let m = n.transform().matrix();
            return Matrix4::from_fn(|r, c| m[c][r] as f64);
        }
        let (t0, r0, s0) = n.transform().decomposed();
        let t = translation
            .get(&i)
            .copied()
            .unwrap_or(Vector3::from(t0).cast());
        let r = rotation.get(&i).copied().unwrap_or(r0.map(|c| c as f64));
        let s = scale.get(&i).copied().unwrap_or(Vector3::from(s0).cast());
        trs_matrix(t, r, s)
    };
    let global = |i: usize| -> Matrix4<f64> {
        let mut m = local(i);
        let mut p = parent[i];
        while let Some(q) = p {
            m = local(q) * m;
            p = parent[q];
        }
        m
    };

    let skinned = doc
        .nodes()
        .find(|n| n.skin().is_some() && n.mesh().is_some())
        .unwrap();
    let skin = skinned.skin().unwrap();
    let ibms: Vec<[[f32; 4]; 4]> = skin
        .reader(get)
        .read_inverse_bind_matrices()
        .unwrap()
        .collect();
    let palette: Vec<Matrix4<f64>> = skin
        .joints()
        .zip(&ibms)
        .map(|(j, ibm)| global(j.index()) * Matrix4::from_fn(|r, c| ibm[c][r] as f64))
        .collect();

    let mut out = Vec::new();
    for prim in skinned.mesh().unwrap().primitives() {
        let r = prim.reader(get);
        let pos: Vec<[f32; 3]> = r.read_positions().unwrap().collect();
        let joints: Vec<[u16; 4]> = r.read_joints(0).unwrap().into_u16().collect();
        let weights: Vec<[f32; 4]> = r.read_weights(0).unwrap().into_f32().collect();
        for ((p, j), w) in pos.iter().zip(&joints).zip(&weights) {
            let h = nalgebra::Vector4::new(p[0] as f64, p[1] as f64, p[2] as f64, 1.0);
            let sum: f64 = w.iter().map(|&x| x as f64).sum();
            let mut acc = nalgebra::Vector4::zeros();
            for k in 0..4 {
                if w[k] > 0.0 {
                    acc += palette[j[k] as usize] * h * (w[k] as f64 / sum);
                }
            }
            out.push([acc.x, acc.y, acc.z]);
        }
    }
    out
}

/// Tolerance: 1e-5 of the model size (`TriMesh::size`, the bounding-box
/// diagonal, about 1.91 for CesiumMan), per coordinate.
#[test]
fn cesium_man_skinning_matches_independent_matrix_palette() {
    let path = asset("CesiumMan.glb");
    let (c, _) = load_character(&path).unwrap();
    let clip = c.clip(None).unwrap();
    let size = c.mesh.size() as f64;
    let mut buffers = PoseBuffers::new(&c);
    let mut worst = 0.0f64;
    // Between keyframes, so rotations are slerped.
    for t in [0.3f32, 1.0123, 1.77] {
        buffers.pose(&c, Some(clip), t);
        buffers.skin_all(&c, SkinningModel::Linear);
        let reference = reference_skinning(&path, t);
        assert_eq!(reference.len(), buffers.positions.len());
        let mut moved = 0.0f64;
        for (v, (ours, theirs)) in buffers.positions.iter().zip(&reference).enumerate() {
            let e = (0..3)
                .map(|i| (ours[i] as f64 - theirs[i]).abs())
                .fold(0.0, f64::max);
            worst = worst.max(e / size);
            assert!(
                e <= 1e-5 * size,
                "t={t} vertex {v}: ours {ours:?}, reference {theirs:?}"
            );
            let bind = c.mesh.positions()[v];
            moved = moved.max(
                (0..3)
                    .map(|i| (bind[i] as f64 - theirs[i]).abs())
                    .fold(0.0, f64::max),
            );
        }
        assert!(
            moved > 0.01 * size,
            "the pose at t={t} should differ from the bind pose"
        );
    }
    eprintln!("max |ours - reference| / model size = {worst:.3e} (model size {size:.4})");
}

// ---------------------------------------------------------------------------
// Generated files.

/// Two joints (node 1 at the origin, node 2 one unit up, its child), a
/// two-triangle quad on mesh node 0. `joints`/`weights` are f32 weights and u16
/// joints per vertex; `extra` is appended to the body (animations).
fn two_bone_file(joints: [[u16; 4]; 4], weights: [[f32; 4]; 4], skin: bool, extra: &str) -> String {
    let mut b = Builder::default();
    let pos = b.f32s(
        &[-0.5, 0.0, 0.0, 0.5, 0.0, 0.0, -0.5, 2.0, 0.0, 0.5, 2.0, 0.0],
        "VEC3",
        3,
    );
    let idx = b.u16s(&[0, 1, 2, 2, 1, 3], "SCALAR", 1, false);
    let j = b.u16s(&joints.concat(), "VEC4", 4, false);
    let w = b.f32s(&weights.concat(), "VEC4", 4);
    let ibm = b.f32s(
        &[
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, //
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 1.0,
        ],
        "MAT4",
        16,
    );
    let times = b.f32s(&[0.0, 1.0], "SCALAR", 1);
    let rot = b.f32s(
        &[
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            std::f32::consts::FRAC_1_SQRT_2,
            std::f32::consts::FRAC_1_SQRT_2,
        ],
        "VEC4",
        4,
    );
    let mesh_node = if skin {
        r#"{"mesh": 0, "skin": 0}"#
    } else {
        r#"{"mesh": 0}"#
    };
    let skins = if skin {
        format!(r#", "skins": [{{"joints": [1, 2], "inverseBindMatrices": {ibm}}}]"#)
    } else {
        String::new()
    };
    b.finish(&format!(
        r#""scene": 0, "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [{mesh_node}, {{"name": "hip", "children": [2]}}, {{"name": "knee", "translation": [0, 1, 0]}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": {pos}, "JOINTS_0": {j}, "WEIGHTS_0": {w}}}, "indices": {idx}}}]}}]{skins},
  "animations": [{{"name": "bend", "samplers": [{{"input": {times}, "output": {rot}}}], "channels": [{{"sampler": 0, "target": {{"node": 2, "path": "rotation"}}}}]}}{extra}]"#
    ))
}

const J: [[u16; 4]; 4] = [[0, 0, 0, 0], [0, 0, 0, 0], [1, 0, 0, 0], [1, 0, 0, 0]];
const W: [[f32; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0, 0.0],
    [0.5, 0.5, 0.0, 0.0],
    [1.0, 0.0, 0.0, 0.0],
];

/// Loads a generated file, expecting an error; returns its message after
/// checking it is one line naming the file.
fn load_error(scratch: &Scratch, name: &str, contents: &str) -> String {
    let path = scratch.write(name, contents);
    let err: LoadError = match load_character(&path) {
        Ok(_) => panic!("{name} should not load"),
        Err(e) => e,
    };
    let msg = err.to_string();
    eprintln!("{msg}");
    assert!(msg.starts_with(&path.display().to_string()), "{msg}");
    assert!(!msg.contains('\n'), "{msg}");
    assert_eq!(err.path(), path);
    msg
}

#[test]
fn generated_two_bone_character_loads_and_bends() {
    let scratch = Scratch::new("ok");
    let path = scratch.write("ok.gltf", two_bone_file(J, W, true, ""));
    let (c, report) = load_character(&path).unwrap();
    assert_eq!(c.skeleton.len(), 2);
    assert_eq!(c.skeleton.joints()[0].name, "hip");
    assert_eq!(c.skeleton.joints()[1].parent.map(|p| p.index()), Some(0));
    assert_eq!(c.mesh.triangle_count(), 2);
    assert!(report.skipped_channels.is_empty());
    let clip = c.clip(Some("bend")).unwrap();
    let mut pose = PoseBuffers::new(&c);
    pose.pose(&c, Some(clip), 1.0);
    pose.skin_all(&c, SkinningModel::Linear);
    // Vertex 3 (0.5, 2, 0), rigid on the knee at (0, 1, 0), turned 90° about z.
    let p = pose.positions[3];
    assert!(
        (p - nalgebra::Point3::new(-1.0, 1.5, 0.0)).norm() < 1e-5,
        "{p:?}"
    );
}

#[test]
fn no_skin_is_an_error() {
    let scratch = Scratch::new("noskin");
    let msg = load_error(&scratch, "noskin.gltf", &two_bone_file(J, W, false, ""));
    assert!(msg.contains("no skin"), "{msg}");
}

#[test]
fn joint_index_out_of_range_is_an_error() {
    let scratch = Scratch::new("range");
    let mut j = J;
    j[2] = [1, 7, 0, 0];
    let msg = load_error(&scratch, "range.gltf", &two_bone_file(j, W, true, ""));
    assert!(
        msg.contains("mesh 0 primitive 0: vertex 2: joint index 7"),
        "{msg}"
    );
    assert!(msg.contains("out of range"), "{msg}");
}

#[test]
fn weights_summing_to_zero_are_an_error() {
    let scratch = Scratch::new("zero");
    let mut w = W;
    w[1] = [0.0; 4];
    let msg = load_error(&scratch, "zero.gltf", &two_bone_file(J, w, true, ""));
    assert!(
        msg.contains("mesh 0 primitive 0: vertex 1: weights sum to 0"),
        "{msg}"
    );
}

#[test]
fn channel_targeting_no_node_is_an_error() {
    let scratch = Scratch::new("nonode");
    let extra = r#", {"samplers": [{"input": 5, "output": 6}], "channels": [{"sampler": 0, "target": {"node": 9, "path": "rotation"}}]}"#;
    let msg = load_error(&scratch, "nonode.gltf", &two_bone_file(J, W, true, extra));
    assert!(
        msg.contains("animation 1 channel 0: channel targeting no node: node 9"),
        "{msg}"
    );
}

#[test]
fn sampler_count_mismatch_is_an_error() {
    let scratch = Scratch::new("count");
    // Accessor 5 has 2 times, accessor 0 (positions, VEC3) 4 elements.
    let extra = r#", {"samplers": [{"input": 5, "output": 0}], "channels": [{"sampler": 0, "target": {"node": 2, "path": "translation"}}]}"#;
    let msg = load_error(&scratch, "count.gltf", &two_bone_file(J, W, true, extra));
    assert!(
        msg.contains("animation 1 channel 0: sampler 0: input has 2 keyframes but output has 4"),
        "{msg}"
    );
}

#[test]
fn unknown_clip_lists_the_clips() {
    let scratch = Scratch::new("clip");
    let path = scratch.write("clip.gltf", two_bone_file(J, W, true, ""));
    let (c, _) = load_character(&path).unwrap();
    let msg = c.clip(Some("nope")).unwrap_err().to_string();
    assert_eq!(msg, r#"no clip named "nope"; clips: bend"#);
}

/// Two primitives, one with u8 joints and normalized u8 weights, one with u16
/// joints and normalized u16 weights; skin joints listed child first; STEP
/// translation, CUBICSPLINE rotation stored as normalized i16, and channels
/// that must be skipped.
#[test]
fn every_influence_and_keyframe_format() {
    let mut b = Builder::default();
    let tri = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let pos0 = b.f32s(&tri, "VEC3", 3);
    let pos1 = b.f32s(&tri, "VEC3", 3);
    // Skin joints [2, 1]: skin joint 0 is the knee (node 2), 1 the hip (node 1).
    let j0 = b.u8s(&[0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0], "VEC4", 4, false);
    let w0 = b.u8s(
        &[255, 0, 0, 0, 255, 0, 0, 0, 128, 127, 0, 0],
        "VEC4",
        4,
        true,
    );
    let j1 = b.u16s(&[1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0], "VEC4", 4, false);
    let w1 = b.u16s(
        &[65535, 0, 0, 0, 16384, 49151, 0, 0, 65535, 0, 0, 0],
        "VEC4",
        4,
        true,
    );
    let times = b.f32s(&[0.0, 1.0, 2.0], "SCALAR", 1);
    let steps = b.f32s(&[0.0, 1.0, 0.0, 0.0, 2.0, 0.0, 0.0, 3.0, 0.0], "VEC3", 3);
    let t2 = b.f32s(&[0.0, 2.0], "SCALAR", 1);
    // CUBICSPLINE: per key in-tangent, value, out-tangent, as normalized i16.
    let h = 23170i16; // round(32767 / sqrt 2)
    let cubic = b.i16s(
        &[
            0, 0, 0, 0, 0, 0, 0, 32767, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, h, h, 0, 0, 0, 0,
        ],
        "VEC4",
        4,
        true,
    );
    let body = format!(
        r#""scene": 0, "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [{{"mesh": 0, "skin": 0}}, {{"name": "hip", "children": [2, 3]}}, {{"name": "knee", "translation": [0, 1, 0]}}, {{"name": "prop", "mesh": 1}}],
  "meshes": [
    {{"primitives": [
      {{"attributes": {{"POSITION": {pos0}, "JOINTS_0": {j0}, "WEIGHTS_0": {w0}}}}},
      {{"attributes": {{"POSITION": {pos1}, "JOINTS_0": {j1}, "WEIGHTS_0": {w1}}}}}]}},
    {{"primitives": [{{"attributes": {{"POSITION": {pos0}}}}}]}}],
  "skins": [{{"joints": [2, 1]}}],
  "animations": [{{"name": "mixed",
    "samplers": [{{"input": {times}, "output": {steps}, "interpolation": "STEP"}},
                 {{"input": {t2}, "output": {cubic}, "interpolation": "CUBICSPLINE"}}],
    "channels": [{{"sampler": 0, "target": {{"node": 2, "path": "translation"}}}},
                 {{"sampler": 1, "target": {{"node": 1, "path": "rotation"}}}},
                 {{"sampler": 0, "target": {{"node": 3, "path": "translation"}}}},
                 {{"sampler": 0, "target": {{"node": 0, "path": "weights"}}}}]}}]"#
    );
    let scratch = Scratch::new("formats");
    let path = scratch.write("formats.gltf", b.finish(&body));
    let (c, report) = load_character(&path).unwrap();

    // Hip first, then knee: skin joint k maps to JointId 1 - k.
    let names: Vec<&str> = c
        .skeleton
        .joints()
        .iter()
        .map(|j| j.name.as_str())
        .collect();
    assert_eq!(names, ["hip", "knee"]);
    assert_eq!(c.skeleton.joints()[1].parent.map(|p| p.index()), Some(0));
    assert_eq!(c.skeleton.joints()[0].inverse_bind, Matrix4::identity());
    // Two skinned primitives and the prop, bound rigidly to the hip.
    assert_eq!(c.mesh.vertex_count(), 9);
    assert_eq!(c.mesh.triangle_count(), 3);

    let inf = |v: usize| -> Vec<(usize, f32)> {
        c.influences.of(v).map(|(j, w)| (j.index(), w)).collect()
    };
    let close = |a: Vec<(usize, f32)>, b: &[(usize, f32)]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| x.0 == y.0 && (x.1 - y.1).abs() < 1e-6)
    };
    assert!(close(inf(0), &[(1, 1.0)]), "{:?}", inf(0));
    assert!(close(inf(1), &[(0, 1.0)]), "{:?}", inf(1));
    assert!(
        close(inf(2), &[(1, 128.0 / 255.0), (0, 127.0 / 255.0)]),
        "{:?}",
        inf(2)
    );
    assert!(close(inf(3), &[(0, 1.0)]), "{:?}", inf(3));
    assert!(
        close(inf(4), &[(1, 16384.0 / 65535.0), (0, 49151.0 / 65535.0)]),
        "{:?}",
        inf(4)
    );
    assert!(close(inf(5), &[(0, 1.0)]), "{:?}", inf(5));
    for v in 6..9 {
        assert!(close(inf(v), &[(0, 1.0)]), "{:?}", inf(v));
        assert_eq!(c.mesh.positions()[v], c.mesh.positions()[v - 6]);
    }

    // The prop mesh is attached to the hip; the prop/morph channels are reported.
    assert!(report.unskinned_meshes.is_empty());
    assert_eq!(
        report.attached_meshes,
        [AttachedMesh {
            node: 3,
            mesh: 1,
            joint_node: 1,
            joint: "hip".into()
        }]
    );
    let skipped: Vec<(usize, &str)> = report
        .skipped_channels
        .iter()
        .map(|s| (s.node, s.property))
        .collect();
    assert_eq!(skipped, [(3, "translation"), (0, "weights")]);
    assert!(
        report.skipped_channels[0].reason.contains("rigid mesh"),
        "{}",
        report.skipped_channels[0]
    );

    let clip = c.clip(Some("mixed")).unwrap();
    assert_eq!(clip.channels.len(), 2);
    let step = &clip.channels[0];
    assert_eq!(
        (step.joint.index(), step.interpolation),
        (1, Interpolation::Step)
    );
    assert_eq!(step.times, [0.0, 1.0, 2.0]);
    assert_eq!(
        step.values,
        ChannelValues::Translation(vec![
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 2.0, 0.0),
            Vector3::new(0.0, 3.0, 0.0)
        ])
    );
    let cubic = &clip.channels[1];
    assert_eq!(
        (cubic.joint.index(), cubic.interpolation),
        (0, Interpolation::CubicSpline)
    );
    let ChannelValues::Rotation(q) = &cubic.values else {
        panic!("rotation expected")
    };
    assert_eq!(q.len(), 6);
    assert_eq!(q[1], Quaternion::new(1.0, 0.0, 0.0, 0.0));
    let s = 23170.0 / 32767.0;
    assert!(
        (q[4] - Quaternion::new(s, 0.0, 0.0, s)).norm() < 1e-7,
        "{:?}",
        q[4]
    );
    assert_eq!(q[0], Quaternion::new(0.0, 0.0, 0.0, 0.0));

    // Sampling: STEP holds the earlier key; the spline hits its keys.
    let mut out = c.skeleton.rest_pose();
    clip.sample(1.5, c.skeleton.rest_pose_ref(), &mut out);
    assert_eq!(out[1].translation, Vector3::new(0.0, 2.0, 0.0));
    clip.sample(2.0, c.skeleton.rest_pose_ref(), &mut out);
    let expected = UnitQuaternion::from_quaternion(Quaternion::new(1.0, 0.0, 0.0, 1.0));
    assert!(out[0].rotation.angle_to(&expected) < 1e-5);
    assert_eq!(clip.duration(), 2.0);
}
