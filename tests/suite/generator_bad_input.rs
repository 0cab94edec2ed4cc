//! Bad wall descriptions and distribution files give an error naming the file and the key,
//! never a panic (lumol's `tests/bad` habit: each bad input carries the expected message).

use drystone::generator::{DistributionSource, Wall};
use std::path::Path;

use crate::common;

const GOOD: &str = r#"
version = 1
name = "bad-input base"

[geometry]
length_m = 1.5
height_m = 0.375
base_width_m = 0.150
top_width_m = 0.077

[arrangement]
kind = "irregular"
dip_deg = "dip_uniform_10"

[courses]
height_m = "course_height_sbl"

[blocks]
length_m = "block_length_sbl"

[[materials]]
name = "shale"
density_kg_per_m3 = 2189
kn_pa_per_m = 5e7
ks_pa_per_m = 2.5e7
friction_deg = 35

[restraints]
base = "held"
"#;

/// A scratch directory of its own for each check (removed when dropped).
fn scratch(name: &str) -> common::Scratch {
    common::Scratch::created(&format!("generator-bad-input-{name}"))
}

fn library() -> DistributionSource {
    DistributionSource::dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("distributions"))
}

/// Writes `text` to a file called `name` and loads it; returns the error message.
fn error_of(name: &str, text: &str, source: &DistributionSource) -> String {
    let dir = scratch(name);
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let r = std::panic::catch_unwind(|| Wall::from_file_with(&path, source).map(|_| ()));
    match r {
        Err(_) => panic!("{name}: the generator panicked"),
        Ok(Ok(())) => panic!("{name}: accepted"),
        Ok(Err(e)) => {
            let msg = e.to_string();
            assert!(msg.contains(&path.display().to_string()), "{name}: the message does not name the file: {msg}");
            msg
        }
    }
}

fn replace(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "{from}");
    GOOD.replacen(from, to, 1)
}

#[track_caller]
fn expect(name: &str, text: &str, keys: &[&str]) {
    let msg = error_of(name, text, &library());
    for k in keys {
        assert!(msg.contains(k), "{name}: expected {k:?} in: {msg}");
    }
}

#[test]
fn the_base_description_is_good() {
    let dir = scratch("good");
    let path = dir.join("good.toml");
    std::fs::write(&path, GOOD).unwrap();
    Wall::from_file_with(&path, &library()).unwrap();
}

#[test]
fn negative_or_zero_dimensions() {
    expect("neg_length.toml", &replace("length_m = 1.5", "length_m = -1.5"), &["geometry.length_m", "-1.5", "> 0"]);
    expect("zero_height.toml", &replace("height_m = 0.375", "height_m = 0"), &["geometry.height_m", "> 0"]);
    expect("zero_base.toml", &replace("base_width_m = 0.150", "base_width_m = 0.0"), &["geometry.base_width_m"]);
    expect("neg_top.toml", &replace("top_width_m = 0.077", "top_width_m = -0.077"), &["geometry.top_width_m"]);
    expect("nan_length.toml", &replace("length_m = 1.5", "length_m = nan"), &["geometry.length_m"]);
    expect(
        "neg_course.toml",
        &replace("height_m = \"course_height_sbl\"", "height_m = -0.05"),
        &["courses.height_m", "> 0"],
    );
    expect("zero_block.toml", &replace("length_m = \"block_length_sbl\"", "length_m = 0.0"), &["blocks.length_m"]);
}

#[test]
fn top_wider_than_base() {
    expect("b_gt_B.toml", &replace("top_width_m = 0.077", "top_width_m = 0.2"), &["geometry.top_width_m", "b ≤ B"]);
}

#[test]
fn dips_outside_minus_90_90() {
    let t = replace("dip_deg = \"dip_uniform_10\"", "dip_deg = \"steep\"")
        + "\n[distributions.steep]\nunit = \"deg\"\nkind = \"uniform\"\nmin = -95.0\nmax = 20.0\n";
    expect("dip_95.toml", &t, &["arrangement.dip_deg", "(-90, 90)"]);
    let t = replace("dip_deg = \"dip_uniform_10\"", "dip_deg = 90.0");
    expect("dip_fixed_90.toml", &t, &["arrangement.dip_deg", "(-90, 90)"]);
    let t = replace("dip_deg = \"dip_uniform_10\"", "dip_deg = \"n\"")
        + "\n[distributions.n]\nunit = \"deg\"\nkind = \"normal\"\nmean = 0.0\nstd = 5.0\n";
    expect("dip_normal.toml", &t, &["arrangement.dip_deg", "truncated_normal"]);
}

#[test]
fn course_height_larger_than_the_wall() {
    expect(
        "course_gt_h.toml",
        &replace("height_m = \"course_height_sbl\"", "height_m = 0.5"),
        &["courses.height_m", "larger than the wall height"],
    );
    expect(
        "block_gt_l.toml",
        &replace("length_m = \"block_length_sbl\"", "length_m = 2.0"),
        &["blocks.length_m", "larger than the wall length"],
    );
}

#[test]
fn unknown_distribution_name_or_key() {
    let msg = error_of("unknown_dist.toml", &replace("\"dip_uniform_10\"", "\"dip_uniform_99\""), &library());
    assert!(
        msg.contains("arrangement.dip_deg") && msg.contains("dip_uniform_99") && msg.contains("unknown distribution"),
        "{msg}"
    );
    assert!(msg.contains("dip_uniform_20"), "lists the available names: {msg}");
    // No distributions directory at all.
    let msg = error_of("no_library.toml", GOOD, &DistributionSource::default());
    assert!(msg.contains("courses.height_m") && msg.contains("course_height_sbl"), "{msg}");
    // Unknown key in the wall file, in a section, and in an inline distribution.
    expect("unknown_key.toml", &replace("[geometry]", "[geometry]\nlenght_m = 1.0"), &["lenght_m"]);
    expect("unknown_top_key.toml", &format!("colour = \"red\"\n{GOOD}"), &["colour"]);
    let t = replace("dip_deg = \"dip_uniform_10\"", "dip_deg = \"d\"")
        + "\n[distributions.d]\nunit = \"deg\"\nkind = \"uniform\"\nmin = -5.0\nmax = 5.0\nstd = 1.0\n";
    expect("inline_extra_key.toml", &t, &["distributions.d.std", "takes only"]);
    let t = replace("dip_deg = \"dip_uniform_10\"", "dip_deg = \"d\"")
        + "\n[distributions.d]\nunit = \"deg\"\nkind = \"uniform\"\nmin = -5.0\nmaks = 5.0\n";
    expect("inline_unknown_key.toml", &t, &["maks"]);
    let t = replace("dip_deg = \"dip_uniform_10\"", "dip_deg = \"d\"")
        + "\n[distributions.d]\nunit = \"deg\"\nkind = \"gaussian\"\nmean = 0.0\nstd = 5.0\n";
    expect("inline_unknown_kind.toml", &t, &["gaussian"]);
    // A distribution of the wrong unit.
    expect(
        "wrong_unit.toml",
        &replace("dip_deg = \"dip_uniform_10\"", "dip_deg = \"block_length_sbl\""),
        &["arrangement.dip_deg", "unit m", "needs deg"],
    );
    // A name that could escape the directory.
    expect("path_name.toml", &replace("\"dip_uniform_10\"", "\"../dip_uniform_10\""), &["arrangement.dip_deg"]);
}

#[test]
fn a_bad_distribution_file_is_named() {
    let scratch = scratch("lib");
    let dir = scratch.join("lib");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("broken.toml"), "version = 1\nunit = \"deg\"\nkind = \"uniform\"\nmin = 5.0\nmax = -5.0\n")
        .unwrap();
    std::fs::write(dir.join("noversion.toml"), "unit = \"deg\"\nkind = \"uniform\"\nmin = -5.0\nmax = 5.0\n").unwrap();
    std::fs::write(
        dir.join("typo.toml"),
        "version = 1\nunit = \"deg\"\nkind = \"uniform\"\nmin = -5.0\nmax = 5.0\nmean = 0\n",
    )
    .unwrap();
    let src =
        DistributionSource { dirs: vec![dir.clone(), Path::new(env!("CARGO_MANIFEST_DIR")).join("distributions")] };
    for (name, key) in [("broken", "max"), ("noversion", "version"), ("typo", "mean")] {
        let path = scratch.join(format!("uses_{name}.toml"));
        std::fs::write(&path, replace("\"dip_uniform_10\"", &format!("\"{name}\""))).unwrap();
        let msg = Wall::from_file_with(&path, &src).unwrap_err().to_string();
        let file = dir.join(format!("{name}.toml")).display().to_string();
        assert!(msg.contains(&file) && msg.contains(key), "{name}: {msg}");
    }
}

#[test]
fn arrangement_and_restraint_keys() {
    expect(
        "overlap_irregular.toml",
        &replace("kind = \"irregular\"", "kind = \"irregular\"\noverlap = 0.5"),
        &["arrangement.overlap", "discontinuous"],
    );
    let t = replace("kind = \"irregular\"\ndip_deg = \"dip_uniform_10\"", "kind = \"discontinuous\"\noverlap = 1.5")
        .replace("length_m = \"block_length_sbl\"", "length_m = 0.1");
    expect("overlap_range.toml", &t, &["arrangement.overlap", "(0, 1)"]);
    let t = replace("kind = \"irregular\"\ndip_deg = \"dip_uniform_10\"", "kind = \"continuous\"");
    expect("continuous_random_length.toml", &t, &["blocks.length_m", "fixed block length"]);
    expect(
        "wedge_fill_range.toml",
        &replace("dip_deg = \"dip_uniform_10\"", "dip_deg = \"dip_uniform_10\"\nwedge_fill = 1.5"),
        &["arrangement.wedge_fill", "[0, 1]"],
    );
    let t = replace("kind = \"irregular\"\ndip_deg = \"dip_uniform_10\"", "kind = \"continuous\"\nwedge_fill = 0.5")
        .replace("length_m = \"block_length_sbl\"", "length_m = 0.1");
    expect("wedge_fill_regular.toml", &t, &["arrangement.wedge_fill", "irregular"]);
    expect("bad_kind.toml", &replace("kind = \"irregular\"", "kind = \"random\""), &["random"]);
    expect(
        "rigid_no_zone.toml",
        &replace("base = \"held\"", "base = \"held\"\nends = { kind = \"rigid\" }"),
        &["restraints.ends.zone_m", "missing"],
    );
    expect(
        "spring_no_k.toml",
        &replace("base = \"held\"", "base = \"held\"\nends = { kind = \"spring\", zone_m = 0.05 }"),
        &["restraints.ends.stiffness_n_per_m"],
    );
    expect(
        "zone_too_big.toml",
        &replace("base = \"held\"", "base = \"held\"\nends = { kind = \"rigid\", zone_m = 1.0 }"),
        &["restraints.ends.zone_m"],
    );
    expect("bad_base.toml", &replace("base = \"held\"", "base = \"glued\""), &["glued"]);
    expect(
        "two_gaps.toml",
        &format!("{GOOD}\n[head_joints]\nmicro_gap_m = 0.001\nvoid_fraction = 0.01\n"),
        &["head_joints", "not both"],
    );
    expect("void_range.toml", &format!("{GOOD}\n[head_joints]\nvoid_fraction = 0.7\n"), &["head_joints.void_fraction"]);
    expect(
        "no_material.toml",
        &replace("length_m = \"block_length_sbl\"", "length_m = \"block_length_sbl\"\nmaterial = \"granite\""),
        &["blocks.material", "granite"],
    );
    expect("neg_kn.toml", &replace("kn_pa_per_m = 5e7", "kn_pa_per_m = -5e7"), &["materials[shale].kn_pa_per_m"]);
    expect("phi_90.toml", &replace("friction_deg = 35", "friction_deg = 90"), &["materials[shale].friction_deg"]);
    expect("version.toml", &replace("version = 1", "version = 2"), &["version"]);
    expect("syntax.toml", &replace("version = 1", "version = = 1"), &["line"]);
    expect("wrong_type.toml", &replace("length_m = 1.5", "length_m = \"long\""), &["length_m"]);
}

#[test]
fn a_missing_file_is_named() {
    let dir = scratch("missing");
    let p = dir.join("does_not_exist.toml");
    let e = Wall::from_file_with(&p, &library()).unwrap_err().to_string();
    assert!(e.contains("does_not_exist.toml"), "{e}");
}

/// Joints softer than a layout accepts (`ρ g / Kn ≤ 0.01`: with ρ 2189 kg/m³ and g 9.81,
/// Kn ≥ 2.147e6 Pa/m) are refused as the wall file's value, naming the key and the
/// resulting Kn, not as "a generator bug" when the generated layout is checked.
#[test]
fn joints_too_soft_for_their_weight_name_the_key_and_the_kn() {
    // A family's factor on the material's Kn: 5e7 × 1e-2 = 5e5 Pa/m.
    let t = GOOD.to_string() + "\n[joints.bed]\nkn_factor = 0.01\n";
    let msg = error_of("soft_factor.toml", &t, &library());
    assert!(msg.contains("joints.bed.kn_factor") && msg.contains("Kn = 5e5 Pa/m"), "{msg}");
    assert!(!msg.contains("generator bug"), "{msg}");
    // A family's own Kn.
    let t = GOOD.to_string() + "\n[joints.head]\nkn_pa_per_m = 1e6\n";
    expect("soft_family.toml", &t, &["joints.head.kn_pa_per_m", "Kn = 1e6 Pa/m", "too soft"]);
    // The material's Kn.
    expect(
        "soft_material.toml",
        &replace("kn_pa_per_m = 5e7", "kn_pa_per_m = 2e6"),
        &["materials[shale].kn_pa_per_m", "Kn = 2e6 Pa/m", "Kn ≥ 2.147"],
    );
    // Just stiff enough is accepted.
    let dir = scratch("stiff_enough");
    let path = dir.join("ok.toml");
    std::fs::write(&path, replace("kn_pa_per_m = 5e7", "kn_pa_per_m = 2.2e6")).unwrap();
    Wall::from_file_with(&path, &library()).unwrap();
}
