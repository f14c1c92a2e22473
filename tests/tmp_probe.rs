use std::path::Path;
use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::scenario::open_scenario;
use cornertree::world::{ContinuousWorld, World};
#[test]
fn probe() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/museum.toml");
    let mut r = open_scenario(&path).unwrap();
    r.methods = vec![cornertree::pipeline::Method::PrunedTriTri];
    r.frames = 33; r.dedup = false;
    let mut world = World::new(r, 1).unwrap();
    world.set_refit_timing(false);
    let mut cw = ContinuousWorld::new(&world, CcdParams::default());
    let (mut tc, mut td) = (0.0, 0.0);
    for rep in 0..30 {
        for k in 0..33 {
            world.pose(k);
            let t0 = std::time::Instant::now();
            world.detect_method(0);
            let d = t0.elapsed().as_secs_f64();
            let t0 = std::time::Instant::now();
            cw.detect(&mut world, k, 0);
            let c = t0.elapsed().as_secs_f64();
            cw.end_frame(&world, k);
            if k > 0 && rep > 0 { td += d; tc += c; }
        }
    }
    println!("discrete {:.3} ms continuous {:.3} ms ratio {:.2}", td * 1e3 / (29.0*32.0), tc * 1e3 / (29.0*32.0), tc / td);
}
