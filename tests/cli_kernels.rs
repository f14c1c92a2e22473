//! `cornertree kernels`: the documented JSON, and one-line errors.

use std::process::Command;

use cornertree::geometry::ops;

fn kernels(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .arg("kernels")
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn json_lists_every_kernel_charged_and_paid() {
    let o = kernels(&["--pairs", "300", "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let list = v["kernels"].as_array().unwrap();
    let charged = [
        ("sphere-sphere", ops::SPHERE_SPHERE),
        ("plane-sphere", ops::PLANE_SPHERE),
        ("plane-sphere-prepared", ops::PLANE_SPHERE),
        ("tri-tri-tropp", ops::TRI_TRI),
        ("tri-tri-edge-crossing", ops::TRI_TRI),
    ];
    let continuous = ["ccd-vertex-face", "ccd-edge-edge", "ccd-tri-tri"];
    assert_eq!(list.len(), charged.len() + continuous.len());
    let named = charged
        .iter()
        .map(|&(name, c)| (name, Some(c)))
        .chain(continuous.iter().map(|&name| (name, None)));
    for (name, c) in named {
        let k = list
            .iter()
            .find(|k| k["name"] == name)
            .unwrap_or_else(|| panic!("{name} missing: {v}"));
        assert_eq!(k["charged_operations"].as_u64(), c, "{k}");
        assert_eq!(k["inputs"], 300, "{k}");
        let mean = k["paid_operations_mean"].as_f64().unwrap();
        let min = k["paid_operations_min"].as_u64().unwrap() as f64;
        let max = k["paid_operations_max"].as_u64().unwrap() as f64;
        assert!(0.0 < min && min <= mean && mean <= max, "{k}");
        assert!(k["ns_per_test"].as_f64().unwrap() > 0.0, "{k}");
        // A mix: some inputs meet, some do not.
        let positives = k["positives"].as_u64().unwrap();
        assert!(positives > 0 && positives < 300, "{k}");
    }
    // Triangle tests branch on the input: their counts vary.
    for name in ["tri-tri-tropp", "tri-tri-edge-crossing"]
        .iter()
        .chain(&continuous)
    {
        let k = list.iter().find(|k| k["name"] == *name).unwrap();
        assert!(k["paid_operations_min"] != k["paid_operations_max"], "{k}");
    }
    assert_eq!(v["pairs"], 300);
}

#[test]
fn text_table_and_zero_pairs_rejected() {
    let o = kernels(&["--pairs", "30"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("tri-tri-tropp") && text.contains("charged"),
        "{text}"
    );

    let o = kernels(&["--pairs", "0"]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--pairs") && err.contains("at least 1"),
        "{err}"
    );
}
