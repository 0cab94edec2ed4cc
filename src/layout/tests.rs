//! Tests of the layout file: a good layout resolves; an unknown key and a negative stiffness are named.

use super::*;

fn one_block() -> String {
    r#"{"version":1,"name":"t","materials":[{"name":"m","density_kg_per_m3":2000,"kn_pa_per_m":1e8,
    "ks_pa_per_m":5e7,"friction_deg":30}],"table":{"material":"m"},
    "blocks":[{"id":"b0","material":"m","vertices":[[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]]}]}"#
        .to_string()
}

#[test]
fn good_layout_resolves() {
    let l = LayoutSpec::from_json(&one_block()).unwrap().resolve().unwrap();
    assert_eq!(l.blocks.len(), 1);
    assert!((l.materials[0].friction - 30f64.to_radians()).abs() < 1e-15);
}

#[test]
fn unknown_key_is_named() {
    let s = one_block().replace("\"friction_deg\"", "\"frictoin_deg\"");
    let e = LayoutSpec::from_json(&s).unwrap_err().to_string();
    assert!(e.contains("frictoin_deg"), "{e}");
}

#[test]
fn negative_stiffness_is_named() {
    let s = one_block().replace("1e8", "-1e8");
    let e = LayoutSpec::from_json(&s).unwrap().resolve().unwrap_err().to_string();
    assert!(e.contains("materials[m].kn_pa_per_m"), "{e}");
}
