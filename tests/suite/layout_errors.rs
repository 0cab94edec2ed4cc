//! Bad layouts get a clear error naming the file, key or block, and a non-zero exit from the
//! CLI, never a panic.

use drystone::layout::LayoutSpec;
use std::process::Command;

use crate::common;

fn good() -> serde_json::Value {
    serde_json::json!({
        "version": 1,
        "materials": [{"name": "m", "density_kg_per_m3": 2000.0, "kn_pa_per_m": 1e8, "ks_pa_per_m": 5e7, "friction_deg": 30.0}],
        "table": {"material": "m"},
        "blocks": [
            {"id": "a", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]]},
            {"id": "b", "material": "m", "vertices": [[0,0,1],[1,0,1],[1,1,1],[0,1,1],[0,0,2],[1,0,2],[1,1,2],[0,1,2]]}
        ]
    })
}

fn error_of(v: &serde_json::Value) -> String {
    match LayoutSpec::from_json(&v.to_string()).and_then(|s| s.resolve()) {
        Ok(_) => panic!("layout accepted: {v}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_good_layout_loads() {
    LayoutSpec::from_json(&good().to_string()).unwrap().resolve().unwrap();
}

/// An edit that spoils the good layout.
type Spoil = Box<dyn Fn(&mut serde_json::Value)>;

#[test]
fn each_bad_layout_names_its_fault() {
    let cases: Vec<(Spoil, &str)> = vec![
        (Box::new(|v| v["materials"][0]["colour"] = "grey".into()), "colour"),
        (Box::new(|v| v["blocks"][0]["mass"] = 3.into()), "mass"),
        (Box::new(|v| v["version"] = 2.into()), "version"),
        (Box::new(|v| v["blocks"][1]["id"] = "a".into()), "duplicate block id"),
        (Box::new(|v| v["materials"][0]["kn_pa_per_m"] = (-1e8).into()), "materials[m].kn_pa_per_m"),
        (Box::new(|v| v["materials"][0]["ks_pa_per_m"] = 0.0.into()), "materials[m].ks_pa_per_m"),
        (Box::new(|v| v["materials"][0]["friction_deg"] = 95.0.into()), "materials[m].friction_deg"),
        (Box::new(|v| v["materials"][0]["cohesion_pa"] = (-5.0).into()), "materials[m].cohesion_pa"),
        (Box::new(|v| v["blocks"][0]["material"] = "granite".into()), "blocks[a].material"),
        (Box::new(|v| v["table"]["material"] = "granite".into()), "table.material"),
        (Box::new(|v| v["blocks"][0]["vertices"] = serde_json::json!([[0, 0, 0], [1, 0, 0], [0, 1, 0]])), "block a"),
        (
            Box::new(|v| v["blocks"][0]["vertices"] = serde_json::json!([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])),
            "block a",
        ),
        (
            Box::new(|v| {
                let mut verts = v["blocks"][0]["vertices"].as_array().unwrap().clone();
                verts.push(serde_json::json!([0.5, 0.5, 0.5]));
                v["blocks"][0]["vertices"] = verts.into();
            }),
            "not convex",
        ),
        (
            Box::new(|v| {
                v["blocks"][1]["vertices"] = serde_json::json!([
                    [0, 0, 0.9],
                    [1, 0, 0.9],
                    [1, 1, 0.9],
                    [0, 1, 0.9],
                    [0, 0, 2],
                    [1, 0, 2],
                    [1, 1, 2],
                    [0, 1, 2]
                ])
            }),
            "blocks a and b overlap",
        ),
        (
            Box::new(|v| {
                v["blocks"][0]["vertices"] = serde_json::json!([
                    [0, 0, -0.1],
                    [1, 0, -0.1],
                    [1, 1, -0.1],
                    [0, 1, -0.1],
                    [0, 0, 1],
                    [1, 0, 1],
                    [1, 1, 1],
                    [0, 1, 1]
                ])
            }),
            "blocks a and table overlap",
        ),
        (
            Box::new(|v| v["restraints"] = serde_json::json!({"ends": [{"blocks": ["a"], "kind": "spring"}]})),
            "stiffness_n_per_m",
        ),
        (
            Box::new(|v| v["restraints"] = serde_json::json!({"ends": [{"blocks": ["z"], "kind": "rigid"}]})),
            "no such block",
        ),
        (Box::new(|v| v["gravity_m_per_s2"] = (-9.81).into()), "gravity_m_per_s2"),
    ];
    for (mutate, expected) in cases {
        let mut v = good();
        mutate(&mut v);
        let e = error_of(&v);
        assert!(e.contains(expected), "expected {expected:?} in: {e}");
    }
}

#[test]
fn nan_is_rejected_not_propagated() {
    // JSON has no NaN literal; a NaN can only arrive through the API. Rejected there too.
    let mut spec = LayoutSpec::from_json(&good().to_string()).unwrap();
    spec.materials[0].kn_pa_per_m = f64::NAN;
    assert!(spec.resolve().unwrap_err().to_string().contains("kn_pa_per_m"));
    let mut spec = LayoutSpec::from_json(&good().to_string()).unwrap();
    spec.blocks[1].vertices[0][2] = f64::NAN;
    assert!(spec.resolve().unwrap_err().to_string().contains("non-finite"));
}

#[test]
fn cli_exits_non_zero_with_the_file_and_key_named() {
    let dir = common::Scratch::created("layout-errors");
    let bad = dir.join("bad.json");
    let mut v = good();
    v["blocks"][0]["colour"] = "red".into();
    std::fs::write(&bad, v.to_string()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_drystone")).arg("tilt").arg(&bad).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("bad.json") && err.contains("colour"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let out = Command::new(env!("CARGO_BIN_EXE_drystone")).arg("tilt").arg(dir.join("missing.json")).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(err.contains("missing.json"), "{err}");
}
