//! Refit containment on real and generated characters: every frame of every
//! clip at 30 fps, both skinning models, both refit rules, tolerance 1e-5 of
//! the model size.

use std::path::Path;

use cornertree::character::{Character, SkinningModel};
use cornertree::choice::Choice;
use cornertree::io::load_character;
use cornertree::sphere_tree::refit::RefitRule;
use cornertree_workbench::humanoid::{HumanoidParams, generate_humanoid};
use cornertree_workbench::report::animate::{AnimateOptions, animate};

fn asset(name: &str) -> Character {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name);
    load_character(&path).unwrap_or_else(|e| panic!("{e}")).0
}

fn check_all_clips(c: &Character) {
    assert!(!c.clips.is_empty(), "{}: no clips", c.name);
    for clip in &c.clips {
        for (model, refit_rule) in [SkinningModel::Paper, SkinningModel::Linear]
            .into_iter()
            .flat_map(|m| RefitRule::ALL.iter().map(move |&r| (m, r)))
        {
            let opts = AnimateOptions {
                model,
                refit_rule,
                clip: Some(clip.name.clone()),
                fps: 30.0,
                sample_every: usize::MAX,
                ..AnimateOptions::default()
            };
            let r = animate(c, &opts).unwrap();
            assert!(r.tolerance <= 1e-5 * c.mesh.size() as f64 + 1e-12);
            assert!(
                r.frames as f32 >= clip.duration() * 30.0,
                "{}: every 30 fps frame",
                c.name
            );
            assert!(r.checks > 0);
            assert_eq!(
                r.violations, 0,
                "{} clip {:?} {:?} {:?}: worst excess {} (tolerance {})",
                c.name, clip.name, model, refit_rule, r.worst_excess, r.tolerance
            );
            eprintln!(
                "{} {:?} {:?} {:?}: {} frames, {} checks, 0 violations, worst excess {:.2e}, tightness mean {:.3}",
                c.name,
                clip.name,
                model,
                refit_rule,
                r.frames,
                r.checks,
                r.worst_excess,
                r.tightness_mean
            );
        }
    }
}

#[test]
fn cesium_man_refit_holds_every_vertex() {
    check_all_clips(&asset("CesiumMan.glb"));
}

#[test]
fn brainstem_refit_holds_every_vertex() {
    check_all_clips(&asset("BrainStem.glb"));
}

#[test]
fn generated_humanoid_refit_holds_every_vertex() {
    check_all_clips(&generate_humanoid(&HumanoidParams::default()).unwrap());
}
