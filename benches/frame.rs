//! One frame of collision detection per method against the parry3d baseline,
//! on the shipped paper-scale scenario (`scenarios/living_room.toml`: the
//! 44,345-vertex humanoid walking 5 mm from the living room's big wall). Each
//! iteration plays the next frame of the walk: pose, on-demand refit with
//! traversal, skinning of the tested vertices, narrow phase. The baseline
//! poses, skins every vertex, refits parry's BVH and tests every candidate
//! pair with parry's triangle-triangle test. De-duplication is off, so the
//! triangle-triangle methods find exactly the baseline's pairs.
//!
//! `cargo bench --bench frame` (`-- pruned` for one method)

#[path = "common/fixtures.rs"]
mod fixtures;

use std::hint::black_box;

use cornertree::character::PoseBuffers;
use cornertree::pipeline::Method;
use cornertree::pipeline::driver::{Pipeline, PipelineOptions};
use cornertree_workbench::truth::ParryReference;
use criterion::{Criterion, criterion_group, criterion_main};

use fixtures::{FrameCycle, scenario};

fn frame(c: &mut Criterion) {
    let name = "living_room";
    let r = scenario(name);
    let character = &r.first().character;
    let env = &r.environment.mesh;
    let options = PipelineOptions {
        dedup: false,
        ..r.pipeline_options(r.first())
    };
    let mut g = c.benchmark_group(format!("frame/{name}"));
    g.sample_size(10);

    let mut buffers = PoseBuffers::new(character);
    let mut parry = ParryReference::new(env, character.mesh.indices()).unwrap();
    let mut pairs = Vec::new();
    let mut cycle = FrameCycle::new(r.frames());
    g.bench_function("parry3d baseline", |b| {
        b.iter(|| {
            r.first()
                .pose_and_skin_frame(&mut buffers, cycle.next_frame());
            parry.update(&buffers.positions).unwrap();
            parry.pairs_f32(&mut pairs);
            black_box(pairs.len())
        })
    });

    for method in Method::ALL {
        let mut p = Pipeline::new(character, env, method, options);
        p.set_refit_timing(false);
        let mut cycle = FrameCycle::new(r.frames());
        g.bench_function(method.name(), |b| {
            b.iter(|| {
                r.first().pose_frame(&mut buffers, cycle.next_frame());
                black_box(p.detect(&buffers, character, env).pairs)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, frame);
criterion_main!(benches);
