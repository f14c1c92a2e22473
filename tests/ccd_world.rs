//! Continuous detection through a world (issue 14, items 4–6).

use std::path::Path;

use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::scenario::open_scenario;
use cornertree::truth::substep::{StepBodies, SubstepTruth};
use cornertree::truth::substep_score::score_step;
use cornertree::world::{ContinuousWorld, World};

#[test]
fn tunnel_probe() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/tunnel.toml");
    let mut r = open_scenario(&path).unwrap();
    r.methods = vec![
        cornertree::pipeline::Method::PrunedTriTri,
        cornertree::pipeline::Method::PlaneSphere,
    ];
    let mut world = World::new(r, 1).unwrap();
    let mut cw = ContinuousWorld::new(&world, CcdParams::default());
    let mut truth = SubstepTruth::new(&world.scene, 256);
    let mut prev: Vec<Vec<cornertree::geometry::Point>> = Vec::new();
    let mut prev_poses = Vec::new();
    for k in 0..world.frames() {
        world.pose(k);
        world.skin_all();
        world.detect_all();
        cw.detect_all(&mut world, k);
        if k > 0 {
            let bodies = StepBodies {
                scene: &world.scene,
                start: prev.iter().map(|v: &Vec<_>| v.as_slice()).collect(),
                end: world
                    .buffers
                    .iter()
                    .map(|b| b.positions.as_slice())
                    .collect(),
                object_start: &prev_poses,
                object_end: &world.object_poses,
            };
            truth.update(&bodies);
            for m in 0..world.methods.len() {
                let o = cw.outcome(m);
                let s = score_step(&truth, o, &bodies, &cw.params);
                let mut classes = std::collections::BTreeMap::new();
                for x in &s.only_continuous {
                    *classes.entry(format!("{:?}", x.class)).or_insert(0) += 1;
                }
                let disc = world.methods[m].outcome.object_pairs.len()
                    + world.methods[m].outcome.room_pairs.len();
                println!(
                    "frame {k} m{m}: ref {} found {} recall {:.3} cont {} (obj {}) disc {} only {:?} early {:?} ms {:.2} ccd {:?}",
                    s.reference,
                    s.found,
                    s.recall,
                    o.pair_count(),
                    o.object_pairs.len(),
                    disc,
                    classes,
                    o.earliest(),
                    o.wall_ms,
                    o.ccd
                );
            }
        }
        prev = world.buffers.iter().map(|b| b.positions.clone()).collect();
        prev_poses = world.object_poses.clone();
    }
}
