//! The plane-sphere experiment (`plane-sphere-study`) applies the condition
//! each row names, and its counters are the pipeline's.

use std::path::PathBuf;

use cornertree::pipeline::Method;
use cornertree_workbench::study::{Factor, conditions, run_study};

fn scenario() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cornertree-study-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("small_living_room.toml");
    std::fs::write(
        &path,
        r#"frames = 2
[character]
source = "generated:humanoid?vertices=1500"
clip = "walk"
skinning = "paper"
[environment]
kind = "living-room"
vertices = 12000
[placement]
gap = { surface = "south wall", metres = 0.005 }
"#,
    )
    .unwrap();
    path
}

#[test]
fn every_condition_is_applied_and_counted() {
    let methods = [Method::PlaneSphere, Method::PlaneSpherePruned];
    let rows = run_study(&scenario(), &methods, None, |_, _| {}).unwrap();
    assert_eq!(rows.len(), conditions().len() * methods.len());
    let base = &rows[0];
    assert_eq!(
        (base.factor, base.method),
        (Factor::Base, Method::PlaneSphere)
    );
    assert_eq!(base.surface_triangles, 2);
    // The literal reading pays plane-sphere tests at leaf pairs next to the
    // wall; the pruned twin tests fewer character spheres.
    assert!(base.plane_sphere_max > 0 && base.largest_division_leaf_met > 0.0);
    assert!(rows[1].sphere_sphere_max < base.sphere_sphere_max);
    for r in &rows {
        assert_eq!(r.frames, 2);
        // Maxima of different counters may come from different frames.
        assert!(
            r.operations_max
                <= 10 * r.sphere_sphere_max + 96 * r.tri_tri_max + 30 * r.plane_sphere_max,
            "{} {}",
            r.setting,
            r.method
        );
        assert!(r.operations_max as f64 >= r.operations_mean);
        match r.factor {
            // The living room's south wall is 8 m long.
            Factor::Position => assert!(
                [-3.0f32, -1.6, 1.6, 3.0]
                    .iter()
                    .any(|a| (r.along_metres - a).abs() < 1e-3),
                "{}: along {}",
                r.setting,
                r.along_metres
            ),
            Factor::Tessellation if r.setting.starts_with("surface split") => {
                let times: u32 = r.setting["surface split ".len()..]
                    .trim_end_matches('x')
                    .parse()
                    .unwrap();
                assert_eq!(r.surface_triangles, 2 * 4usize.pow(times), "{}", r.setting);
            }
            Factor::Threshold => assert!(r.threshold > 0.15),
            Factor::Dedup => assert!(!r.dedup),
            _ => {}
        }
    }
}
