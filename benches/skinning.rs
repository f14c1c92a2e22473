//! Per-frame character work outside collision detection: posing (joint
//! matrices), skinning every vertex under both models, and refitting every
//! sphere of the character's tree (paper §3). Throughput is per vertex or per
//! sphere.
//!
//! `cargo bench --bench skinning`

#[path = "common/fixtures.rs"]
mod fixtures;

use std::hint::black_box;

use cornertree::character::{PoseBuffers, SkinningModel};
use cornertree::mesh::EdgeDedup;
use cornertree::pipeline::Method;
use cornertree::sphere_tree::BuildParams;
use cornertree::sphere_tree::character::CharacterTree;
use cornertree::sphere_tree::refit::{RefitState, Refitter};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use fixtures::{FrameCycle, scenario};

/// CesiumMan (3,273 vertices) and the paper-scale humanoid (44,345).
const CHARACTERS: [&str; 2] = ["cesium_man", "living_room"];

fn skinning(c: &mut Criterion) {
    for name in CHARACTERS {
        let r = scenario(name);
        let character = &r.first().character;
        let vertices = character.mesh.positions().len();
        let mut g = c.benchmark_group(format!("pose_and_skin/{name}"));
        g.sample_size(20);
        let mut buffers = PoseBuffers::new(character);
        let mut cycle = FrameCycle::new(r.frames());
        g.throughput(Throughput::Elements(character.skeleton.len() as u64));
        g.bench_function("pose joints", |b| {
            b.iter(|| black_box(r.first().pose_frame(&mut buffers, cycle.next_frame())))
        });
        g.throughput(Throughput::Elements(vertices as u64));
        for (label, model) in [
            ("skin all, linear blend", SkinningModel::Linear),
            ("skin all, paper model", SkinningModel::Paper),
        ] {
            r.first().pose_frame(&mut buffers, 3);
            g.bench_function(label, |b| {
                b.iter(|| {
                    buffers.skin_all(character, model);
                    black_box(&buffers.positions);
                })
            });
        }
        g.finish();
    }
}

fn full_refit(c: &mut Criterion) {
    for name in CHARACTERS {
        let r = scenario(name);
        let character = &r.first().character;
        let mut g = c.benchmark_group(format!("refit/{name}"));
        g.sample_size(20);
        // The paper's methods refit by the corner rule, ours by joint balls
        // (`Method::refit_rule`); the tree is the same.
        for (label, method) in [
            ("every sphere, paper corners", Method::Original),
            ("every sphere, joint balls", Method::UndividedPrunedTriTri),
        ] {
            let tree = CharacterTree::build_with_rule(
                character,
                &EdgeDedup::keep_all(&character.mesh),
                r.first().skinning,
                method.character_build(BuildParams::default()),
                method.refit_rule(),
            );
            let mut state = RefitState::new(&tree, character.skeleton.len());
            g.throughput(Throughput::Elements(tree.tree.len() as u64));
            let mut buffers = PoseBuffers::new(character);
            let mut cycle = FrameCycle::new(r.frames());
            g.bench_function(label, |b| {
                b.iter(|| {
                    r.first().pose_frame(&mut buffers, cycle.next_frame());
                    state.begin_frame_with_base(&buffers.skin, &buffers.base);
                    Refitter {
                        tree: &tree,
                        skin: &buffers.skin,
                        state: &mut state,
                    }
                    .refit_all(&buffers.base);
                    black_box(state.spheres.len())
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, skinning, full_refit);
criterion_main!(benches);
