//! `cornertree tables`: Table 1 by construction, room sizes, per-method costs.

use std::process::Command;

#[test]
fn tables_json_has_table1_and_rooms() {
    let out = Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .args(["tables", "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let t1 = &v["table1"];
    assert_eq!(
        t1["corner_tree"],
        serde_json::json!([1, 4, 12, 36, 84, 180, 372])
    );
    assert_eq!(
        t1["quaternary"],
        serde_json::json!([1, 4, 16, 64, 256, 1024, 4096])
    );
    for (room, paper_vertices) in [("museum", 9482.0), ("living_room", 133139.0)] {
        let e = &v["environments"][room];
        let vertices = e["vertices"].as_f64().unwrap();
        assert!(
            (vertices / paper_vertices - 1.0).abs() <= 0.01,
            "{room}: {vertices}"
        );
        assert!(e["triangles"].as_u64().unwrap() > 0);
        assert!(e["big_triangles"].as_u64().unwrap() > 0);
        let cost = |m: &str, k: &str| e[m][k].as_u64().unwrap_or_else(|| panic!("{room}.{m}.{k}"));
        // Original has one leaf per triangle and nothing inside big triangles.
        assert!(cost("original", "nodes") >= e["triangles"].as_u64().unwrap());
        assert_eq!(cost("original", "division_nodes"), 0);
        // The corner-tree is smaller than the full quaternary hierarchy.
        assert!(cost("plane-sphere", "nodes") < cost("quaternary-plane-sphere", "nodes"));
        assert_eq!(
            cost("sphere-division", "nodes"),
            cost("quaternary-plane-sphere", "nodes")
        );
        assert_eq!(
            cost("plane-sphere", "bytes"),
            24 * cost("plane-sphere", "nodes")
        );
    }
}

#[test]
fn tables_rejects_a_missing_scene() {
    let out = Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .args(["tables", "--scene", "no/such/room.glb"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        err.contains("no/such/room.glb") && !err.contains("panicked"),
        "{err}"
    );
}
