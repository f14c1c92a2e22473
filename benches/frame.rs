//! One frame of collision detection per method against the parry3d baseline,
//! on the shipped paper-scale scenario (`scenarios/living_room.toml`: the
//! 44,345-vertex humanoid walking 5 mm from the living room's big wall). Each
//! iteration plays the next frame of the walk through the method's world of
//! a [`Session`] (what `bench` measures): pose, on-demand refit with
//! traversal, skinning of the tested vertices, narrow phase. The baseline
//! ([`ParryWorld`], `bench`'s) poses, skins every vertex, refits parry's BVH
//! and tests every candidate pair with parry's triangle-triangle test.
//! De-duplication is off, so the triangle-triangle methods find exactly the
//! baseline's pairs.
//!
//! `cargo bench --bench frame` (`-- pruned` for one method;
//! `FRAME_SCENARIO=crowd` for another shipped scenario)

#[path = "common/fixtures.rs"]
mod fixtures;

use std::hint::black_box;

use cornertree::pipeline::Method;
use cornertree_workbench::session::Session;
use cornertree_workbench::truth::ParryWorld;
use criterion::{Criterion, criterion_group, criterion_main};

use fixtures::{FrameCycle, scenario};

fn frame(c: &mut Criterion) {
    // Another shipped scenario by name: `FRAME_SCENARIO=crowd cargo bench
    // --bench frame` (with `-- --profile-time 20` under a profiler).
    let name = std::env::var("FRAME_SCENARIO").unwrap_or_else(|_| "living_room".into());
    let name = name.as_str();
    let mut r = scenario(name);
    r.dedup = false;
    r.methods = Method::ALL.to_vec();
    let frames = r.frames();
    // One thread, as the baseline's: one character is one pass anyway.
    let mut session = Session::new(r, 1).unwrap();
    // Refit is timed with traversal: splitting it costs time.
    session.set_refit_timing(false);
    let mut parry = ParryWorld::new(&session.scene).unwrap();
    let mut g = c.benchmark_group(format!("frame/{name}"));
    g.sample_size(10);

    let mut cycle = FrameCycle::new(frames);
    g.bench_function("parry3d baseline", |b| {
        b.iter(|| {
            session.pose_on_one_thread(cycle.next_frame());
            session.skin_all();
            parry
                .update(&session.buffers, &session.object_poses)
                .unwrap();
            parry.detect();
            black_box(parry.pairs.environment.len())
        })
    });

    let methods: Vec<Method> = session.methods().collect();
    for (m, method) in methods.into_iter().enumerate() {
        let mut cycle = FrameCycle::new(frames);
        g.bench_function(method.name(), |b| {
            b.iter(|| {
                session.pose_on_one_thread(cycle.next_frame());
                session.detect(m);
                black_box(session.contacts(m).total.pairs)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, frame);
criterion_main!(benches);
