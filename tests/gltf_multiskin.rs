//! Characters as users bring them: several skins over one skeleton (the same
//! joints with different inverse bind matrices, and a joint subset), and a
//! rigid prop parented to a joint, in one generated file. Posed positions are
//! checked against glTF's skinning formula computed here from the file's own
//! numbers (`Σ w · World(joint) · IBM_skin(joint) · v`, and `World(node) · v`
//! for the prop), and the sphere tree built on the result must contain every
//! skinned vertex (`inspect --animate`'s check).

mod common;
use common::Scratch;
use common::gltf_builder::Builder;

use cornertree::character::{PoseBuffers, SkinningModel};
use cornertree::io::{AttachedMesh, load_character};
use cornertree_workbench::report::animate::{AnimateOptions, animate};
use nalgebra::{Matrix4, Point3, UnitQuaternion, Vector3, Vector4};

/// A quaternion `[x, y, z, w]` turning `angle` radians about `axis`.
fn quat(axis: [f32; 3], angle: f32) -> [f32; 4] {
    let q =
        UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(Vector3::from(axis)), angle);
    [q.i, q.j, q.k, q.w]
}

fn column_major(m: &Matrix4<f64>) -> Vec<f32> {
    m.iter().map(|&x| x as f32).collect()
}

fn translation(x: f64, y: f64, z: f64) -> Matrix4<f64> {
    Matrix4::new_translation(&Vector3::new(x, y, z))
}

/// Node TRS as stored: translation, rotation `[x, y, z, w]`, scale.
#[derive(Clone, Copy)]
struct Node {
    t: [f32; 3],
    r: [f32; 4],
    s: [f32; 3],
}

const REST: Node = Node {
    t: [0.0; 3],
    r: [0.0, 0.0, 0.0, 1.0],
    s: [1.0; 3],
};

/// Nodes 0 root, 1 upper, 2 lower (joints, a chain); 3 grip (not a joint,
/// below lower); 4 prop (a mesh without skin, below grip); 5 body, 6 coat,
/// 7 sleeve (skinned meshes); 8 ground (a mesh without skin at the root).
fn rest_nodes() -> [Node; 9] {
    let mut n = [REST; 9];
    n[0].t = [0.0, 0.5, 0.0];
    n[1].t = [0.0, 1.0, 0.0];
    n[2].t = [0.0, 1.0, 0.0];
    n[3] = Node {
        t: [0.3, 0.6, 0.0],
        r: quat([0.0, 0.0, 1.0], 0.5),
        s: [1.0; 3],
    };
    n[4].s = [0.5, 0.5, 0.5];
    // Skinned nodes' own transforms are ignored by glTF skinning.
    n[5].t = [5.0, 5.0, 5.0];
    n[8].t = [0.0, -0.2, 0.0];
    n
}

const PARENT: [Option<usize>; 9] = [
    None,
    Some(0),
    Some(1),
    Some(2),
    Some(3),
    None,
    None,
    None,
    None,
];

/// Keyframes of the "move" clip (times 0, 1, 2; LINEAR): root translation
/// and rotation, upper rotation and scale, lower rotation.
struct Keys {
    root_t: [[f32; 3]; 3],
    root_r: [[f32; 4]; 3],
    upper_r: [[f32; 4]; 3],
    upper_s: [[f32; 3]; 3],
    lower_r: [[f32; 4]; 3],
}

fn keys() -> Keys {
    let y = [0.0, 1.0, 0.0];
    let z = [0.0, 0.0, 1.0];
    let x = [1.0, 0.0, 0.0];
    Keys {
        root_t: [[0.0, 0.5, 0.0], [0.2, 0.5, 0.1], [0.0, 0.6, 0.0]],
        root_r: [quat(y, 0.0), quat(y, 0.7), quat(y, -0.35)],
        upper_r: [quat(z, 0.0), quat(z, 0.9), quat(z, 0.2)],
        upper_s: [[1.0; 3], [1.1, 0.9, 1.0], [1.0; 3]],
        lower_r: [quat(x, 0.0), quat(x, -1.0), quat(x, 0.5)],
    }
}

/// A skinned strip: two columns of vertices (`x0`, `x1`) at depth `z`, rows
/// at heights `ys`; each row's influences given by `weights(y)` as (skin
/// entry, weight) pairs.
struct Strip {
    positions: Vec<[f64; 3]>,
    indices: Vec<u16>,
    joints: Vec<[u16; 4]>,
    weights: Vec<[f32; 4]>,
}

fn strip(x0: f64, x1: f64, z: f64, ys: &[f64], weights: &dyn Fn(f64) -> Vec<(u16, f32)>) -> Strip {
    let mut s = Strip {
        positions: Vec::new(),
        indices: Vec::new(),
        joints: Vec::new(),
        weights: Vec::new(),
    };
    for (row, &y) in ys.iter().enumerate() {
        for x in [x0, x1] {
            s.positions.push([x, y, z]);
            let mut j = [0u16; 4];
            let mut w = [0f32; 4];
            for (k, (jk, wk)) in weights(y).into_iter().enumerate() {
                j[k] = jk;
                w[k] = wk;
            }
            s.joints.push(j);
            s.weights.push(w);
        }
        if row > 0 {
            let a = 2 * (row as u16 - 1);
            s.indices.extend([a, a + 1, a + 2, a + 2, a + 1, a + 3]);
        }
    }
    s
}

/// A blend from entry `a` (at `y0`) to entry `b` (at `y1`).
fn blend(a: u16, b: u16, y0: f64, y1: f64, y: f64) -> Vec<(u16, f32)> {
    let t = ((y - y0) / (y1 - y0)).clamp(0.0, 1.0) as f32;
    if t <= 0.0 {
        vec![(a, 1.0)]
    } else if t >= 1.0 {
        vec![(b, 1.0)]
    } else {
        vec![(a, 1.0 - t), (b, t)]
    }
}

/// The skins: (joint nodes, inverse bind matrices), as written.
fn skins() -> Vec<(Vec<usize>, Vec<Matrix4<f64>>)> {
    // Inverse rest world transforms of root, upper, lower.
    let ibm0 = [
        translation(0.0, -0.5, 0.0),
        translation(0.0, -1.5, 0.0),
        translation(0.0, -2.5, 0.0),
    ];
    // Skin 1: every joint, listed lower, root, upper, in a bind space moved by
    // one transform `b` (its vertices can move into skin 0's bind space).
    let b = translation(1.0, 0.0, 0.5)
        * UnitQuaternion::from_euler_angles(0.0, 0.0, 0.4).to_homogeneous()
        * Matrix4::new_scaling(1.25);
    // Skin 2: lower and upper only; lower's matrix differs from skin 0's,
    // upper's is the same (vertices on both need a joint slot of their own).
    let lower2 = ibm0[2] * translation(0.0, 0.0, 0.3);
    vec![
        (vec![0, 1, 2], ibm0.to_vec()),
        (vec![2, 0, 1], vec![ibm0[2] * b, ibm0[0] * b, ibm0[1] * b]),
        (vec![2, 1], vec![lower2, ibm0[1]]),
    ]
}

/// The meshes in the loader's vertex order (body, coat, sleeve, then the
/// prop) with their skin, or `None` for the prop. `bad_sleeve_joint` puts a
/// joint index past skin 2's two joints on the sleeve's first vertex.
fn meshes(bad_sleeve_joint: bool) -> Vec<(Strip, Option<usize>)> {
    let ys: Vec<f64> = (0..=10).map(|i| 0.5 + 0.25 * i as f64).collect();
    // Skin 0 entries: 0 root, 1 upper, 2 lower.
    let body = strip(-0.3, 0.3, 0.0, &ys, &|y| {
        if y < 1.5 {
            blend(0, 1, 1.0, 1.5, y)
        } else {
            blend(1, 2, 2.2, 2.8, y)
        }
    });
    // Skin 1 entries: 0 lower, 1 root, 2 upper; stored in its bind space.
    let mut coat = strip(-0.35, 0.35, 0.2, &ys, &|y| {
        if y < 1.5 {
            blend(1, 2, 1.0, 1.5, y)
        } else {
            blend(2, 0, 2.2, 2.8, y)
        }
    });
    let (_, ibm1) = &skins()[1];
    let b_inverse = ibm1[0].try_inverse().unwrap() * translation(0.0, -2.5, 0.0);
    for p in &mut coat.positions {
        let q = b_inverse.transform_point(&Point3::from(*p));
        *p = [q.x, q.y, q.z];
    }
    // Skin 2 entries: 0 lower, 1 upper: upper only, blended, lower only.
    let sleeve_ys: Vec<f64> = (0..=6).map(|i| 1.5 + 0.25 * i as f64).collect();
    let mut sleeve = strip(0.35, 0.5, 0.0, &sleeve_ys, &|y| blend(1, 0, 1.9, 2.6, y));
    if bad_sleeve_joint {
        sleeve.joints[0][0] = 2;
    }
    let prop = strip(-0.1, 0.1, 0.05, &[0.0, 0.3], &|_| vec![]);
    vec![
        (body, Some(0)),
        (coat, Some(1)),
        (sleeve, Some(2)),
        (prop, None),
    ]
}

fn file(bad_sleeve_joint: bool) -> String {
    let mut b = Builder::default();
    let mut mesh_json = Vec::new();
    for (strip, skin) in meshes(bad_sleeve_joint) {
        let flat: Vec<f32> = strip
            .positions
            .iter()
            .flatten()
            .map(|&c| c as f32)
            .collect();
        let pos = b.f32s(&flat, "VEC3", 3);
        let idx = b.u16s(&strip.indices, "SCALAR", 1, false);
        let attributes = if skin.is_some() {
            let j = b.u16s(&strip.joints.concat(), "VEC4", 4, false);
            let w = b.f32s(&strip.weights.concat(), "VEC4", 4);
            format!(r#""POSITION": {pos}, "JOINTS_0": {j}, "WEIGHTS_0": {w}"#)
        } else {
            format!(r#""POSITION": {pos}"#)
        };
        mesh_json.push(format!(
            r#"{{"primitives": [{{"attributes": {{{attributes}}}, "indices": {idx}}}]}}"#
        ));
    }
    let mut skin_json = Vec::new();
    for (joints, ibms) in skins() {
        let flat: Vec<f32> = ibms.iter().flat_map(column_major).collect();
        let a = b.f32s(&flat, "MAT4", 16);
        let joints: Vec<String> = joints.iter().map(usize::to_string).collect();
        skin_json.push(format!(
            r#"{{"joints": [{}], "inverseBindMatrices": {a}}}"#,
            joints.join(", ")
        ));
    }
    let k = keys();
    let times = b.f32s(&[0.0, 1.0, 2.0], "SCALAR", 1);
    let root_t = b.f32s(&k.root_t.concat(), "VEC3", 3);
    let root_r = b.f32s(&k.root_r.concat(), "VEC4", 4);
    let upper_r = b.f32s(&k.upper_r.concat(), "VEC4", 4);
    let upper_s = b.f32s(&k.upper_s.concat(), "VEC3", 3);
    let lower_r = b.f32s(&k.lower_r.concat(), "VEC4", 4);

    let names = [
        "root", "upper", "lower", "grip", "prop", "body", "coat", "sleeve", "ground",
    ];
    let extra = [
        r#", "children": [1]"#,
        r#", "children": [2]"#,
        r#", "children": [3]"#,
        r#", "children": [4]"#,
        r#", "mesh": 3"#,
        r#", "mesh": 0, "skin": 0"#,
        r#", "mesh": 1, "skin": 1"#,
        r#", "mesh": 2, "skin": 2"#,
        r#", "mesh": 3"#,
    ];
    let nodes: Vec<String> = rest_nodes()
        .iter()
        .zip(names)
        .zip(extra)
        .map(|((n, name), extra)| {
            format!(
                r#"{{"name": "{name}", "translation": {:?}, "rotation": {:?}, "scale": {:?}{extra}}}"#,
                n.t, n.r, n.s
            )
        })
        .collect();
    let body = format!(
        r#""scene": 0, "scenes": [{{"nodes": [0, 5, 6, 7, 8]}}],
  "nodes": [{nodes}],
  "meshes": [{meshes}],
  "skins": [{skins}],
  "animations": [
    {{"name": "move",
      "samplers": [{{"input": {times}, "output": {root_t}}}, {{"input": {times}, "output": {root_r}}},
                   {{"input": {times}, "output": {upper_r}}}, {{"input": {times}, "output": {upper_s}}},
                   {{"input": {times}, "output": {lower_r}}}],
      "channels": [{{"sampler": 0, "target": {{"node": 0, "path": "translation"}}}},
                   {{"sampler": 1, "target": {{"node": 0, "path": "rotation"}}}},
                   {{"sampler": 2, "target": {{"node": 1, "path": "rotation"}}}},
                   {{"sampler": 3, "target": {{"node": 1, "path": "scale"}}}},
                   {{"sampler": 4, "target": {{"node": 2, "path": "rotation"}}}}]}},
    {{"name": "wiggle",
      "samplers": [{{"input": {times}, "output": {root_t}}}],
      "channels": [{{"sampler": 0, "target": {{"node": 4, "path": "translation"}}}},
                   {{"sampler": 0, "target": {{"node": 3, "path": "translation"}}}}]}}]"#,
        nodes = nodes.join(",\n    "),
        meshes = mesh_json.join(", "),
        skins = skin_json.join(", "),
    );
    b.finish(&body)
}

/// Linear interpolation of three keys at times 0, 1, 2 (clamped).
fn lerp3(v: &[[f32; 3]; 3], t: f64) -> Vector3<f64> {
    let (k, s) = key(t);
    let a = Vector3::from(v[k]).cast::<f64>();
    let b = Vector3::from(v[(k + 1).min(2)]).cast::<f64>();
    a * (1.0 - s) + b * s
}

/// Spherical interpolation of three rotation keys.
fn slerp3(v: &[[f32; 4]; 3], t: f64) -> UnitQuaternion<f64> {
    let (k, s) = key(t);
    let q = |i: usize| {
        let [x, y, z, w] = v[i].map(f64::from);
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z))
    };
    q(k).slerp(&q((k + 1).min(2)), s)
}

fn key(t: f64) -> (usize, f64) {
    let t = t.clamp(0.0, 2.0);
    let k = (t.floor() as usize).min(1);
    (k, t - k as f64)
}

fn trs(t: Vector3<f64>, r: UnitQuaternion<f64>, s: Vector3<f64>) -> Matrix4<f64> {
    Matrix4::new_translation(&t) * r.to_homogeneous() * Matrix4::new_nonuniform_scaling(&s)
}

/// World matrix of every node at time `t` of "move", from the file's numbers.
fn world_matrices(t: f64) -> Vec<Matrix4<f64>> {
    let k = keys();
    let nodes = rest_nodes();
    let mut world: Vec<Matrix4<f64>> = Vec::new();
    for (i, n) in nodes.iter().enumerate() {
        let [x, y, z, w] = n.r.map(f64::from);
        let mut tr = Vector3::from(n.t).cast::<f64>();
        let mut r = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
        let mut s = Vector3::from(n.s).cast::<f64>();
        match i {
            0 => {
                tr = lerp3(&k.root_t, t);
                r = slerp3(&k.root_r, t);
            }
            1 => {
                r = slerp3(&k.upper_r, t);
                s = lerp3(&k.upper_s, t);
            }
            2 => r = slerp3(&k.lower_r, t),
            _ => {}
        }
        let local = trs(tr, r, s);
        world.push(match PARENT[i] {
            Some(p) => world[p] * local,
            None => local,
        });
    }
    world
}

/// glTF's skinned positions of every character vertex at time `t`.
fn reference(t: f64) -> Vec<Point3<f64>> {
    let world = world_matrices(t);
    let skins = skins();
    let mut out = Vec::new();
    for (strip, skin) in meshes(false) {
        for (v, p) in strip.positions.iter().enumerate() {
            let p = p.map(|c| c as f32 as f64);
            let h = Vector4::new(p[0], p[1], p[2], 1.0);
            let q = match skin {
                None => world[4] * h,
                Some(s) => {
                    let (joints, ibms) = &skins[s];
                    let ibms: Vec<Matrix4<f64>> =
                        ibms.iter().map(|m| m.cast::<f32>().cast()).collect();
                    let mut acc = Vector4::zeros();
                    for k in 0..4 {
                        let w = strip.weights[v][k] as f64;
                        if w > 0.0 {
                            let j = strip.joints[v][k] as usize;
                            acc += world[joints[j]] * ibms[j] * h * w;
                        }
                    }
                    acc
                }
            };
            out.push(Point3::new(q.x, q.y, q.z));
        }
    }
    out
}

#[test]
fn several_skins_and_a_prop_load_as_one_character_and_skin_as_gltf_says() {
    let scratch = Scratch::new("multiskin");
    let path = scratch.write("multiskin.gltf", file(false));
    let (c, report) = load_character(&path).unwrap_or_else(|e| panic!("{e}"));
    for note in &report.notes {
        eprintln!("note: {note}");
    }

    // One skeleton: the three joints, plus one slot for skin 2's lower.
    assert_eq!(report.skins, [0, 1, 2]);
    assert_eq!(report.skinned_instances, 3);
    assert_eq!(report.added_joint_slots, 1);
    assert_eq!(c.skeleton.len(), 4);
    let names: Vec<&str> = c
        .skeleton
        .joints()
        .iter()
        .map(|j| j.name.as_str())
        .collect();
    assert_eq!(&names[..3], ["root", "upper", "lower"]);
    assert_eq!(c.skeleton.joints()[3].parent.map(|p| p.index()), Some(2));
    // Moved into skin 0's bind space: every coat vertex, and the sleeve's
    // vertices on lower alone.
    let meshes = meshes(false);
    let lower_only = meshes[2]
        .0
        .weights
        .iter()
        .zip(&meshes[2].0.joints)
        .filter(|(w, j)| w[0] == 1.0 && j[0] == 0)
        .count();
    assert!(lower_only > 0);
    assert_eq!(
        report.moved_vertices,
        meshes[1].0.positions.len() + lower_only
    );
    // The prop hangs from lower; the ground from no joint.
    assert_eq!(
        report.attached_meshes,
        [AttachedMesh {
            node: 4,
            mesh: 3,
            joint_node: 2,
            joint: "lower".into()
        }]
    );
    assert_eq!(report.unskinned_meshes, [8]);
    let skipped: Vec<(usize, usize, &str)> = report
        .skipped_channels
        .iter()
        .map(|s| (s.animation, s.node, s.reason.as_str()))
        .collect();
    assert_eq!(skipped.len(), 2);
    assert!(skipped[0].0 == 1 && skipped[0].1 == 4 && skipped[0].2.contains("rigid mesh"));
    assert!(skipped[1].0 == 1 && skipped[1].1 == 3);

    // Posed positions against glTF's formula, between keys and at rest.
    let total: usize = meshes.iter().map(|(s, _)| s.positions.len()).sum();
    assert_eq!(c.mesh.vertex_count(), total);
    let clip = c.clip(Some("move")).unwrap();
    let size = c.mesh.size() as f64;
    let mut pose = PoseBuffers::new(&c);
    let mut worst = 0.0f64;
    for t in [0.0f32, 0.45, 1.3, 2.0] {
        pose.pose(&c, Some(clip), t);
        pose.skin_all(&c, SkinningModel::Linear);
        let want = reference(f64::from(t));
        assert_eq!(want.len(), pose.positions.len());
        for (v, (ours, theirs)) in pose.positions.iter().zip(&want).enumerate() {
            let e = (ours.cast::<f64>() - theirs).abs().max();
            worst = worst.max(e / size);
            assert!(
                e <= 1e-5 * size,
                "t={t} vertex {v}: ours {ours:?}, glTF {theirs:?}"
            );
        }
    }
    eprintln!("max |ours - glTF| / model size = {worst:.3e}");
    // The pose moves the vertices (the check is not of a still character).
    let rest = reference(0.0);
    let moved = reference(1.3)
        .iter()
        .zip(&rest)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    assert!(moved > 0.1 * size, "{moved}");

    // The sphere tree refit on it holds every skinned vertex, both models.
    for model in [SkinningModel::Linear, SkinningModel::Paper] {
        let opts = AnimateOptions {
            model,
            clip: Some("move".into()),
            fps: 30.0,
            sample_every: usize::MAX,
            ..AnimateOptions::default()
        };
        let r = animate(&c, &opts).unwrap();
        assert!(r.checks > 0);
        assert_eq!(
            r.violations, 0,
            "{model:?}: worst excess {} (tolerance {})",
            r.worst_excess, r.tolerance
        );
    }
}

#[test]
fn a_joint_index_past_its_own_skin_is_an_error_even_inside_the_skeleton() {
    let scratch = Scratch::new("multiskin-range");
    let path = scratch.write("range.gltf", file(true));
    let msg = match load_character(&path) {
        Ok(_) => panic!("range.gltf should not load"),
        Err(e) => e.to_string(),
    };
    assert!(msg.starts_with(&path.display().to_string()), "{msg}");
    assert!(!msg.contains('\n'), "{msg}");
    assert!(
        msg.contains(
            "mesh 2 primitive 0: vertex 0: joint index 2 (with non-zero weight) is out of range; skin 2 has 2 joints"
        ),
        "{msg}"
    );
}
