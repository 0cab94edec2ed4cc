//! Tests of the observations: the measurement σ the data show beyond the model.

use super::*;

fn obs(specimen: &str, v: f64) -> Observation {
    Observation {
        specimen: specimen.into(),
        group: "G".into(),
        observable: Observable::CollapseAngle,
        value: v,
        sigma: 0.5,
    }
}

/// Two keys whose data spread by a known variance beyond the model's: the excess comes
/// back; a shift of one key's mean changes nothing; too few specimens give nothing.
#[test]
fn the_measurement_sigma_is_the_spread_the_model_does_not_have() {
    // Key 0: values 10 ± 1 (sample variance 4/3 · ... computed below); key 1 the same
    // pattern around 30.
    let a = [9.0, 10.0, 11.0, 10.0];
    let b = [29.0, 30.0, 31.0, 30.0];
    let mut o: Vec<Observation> = a.iter().map(|v| obs("a", *v)).collect();
    o.extend(b.iter().map(|v| obs("b", *v)));
    let key = [0, 0, 0, 0, 1, 1, 1, 1];
    let s2 = 2.0 / 3.0; // sample variance of (−1, 0, 1, 0)
    let (sd, dof) = measurement_sigma(&o, &key, &[0.5, 0.5], 0.0, Family::CollapseAngle).unwrap();
    assert_eq!(dof, 6);
    assert!((sd - (s2 - 0.25f64).sqrt()).abs() < 1e-12, "{sd}");
    // A mean shift of key 1 by 5: the same estimate.
    for v in &mut o[4..] {
        v.value += 5.0;
    }
    assert_eq!(measurement_sigma(&o, &key, &[0.5, 0.5], 0.0, Family::CollapseAngle).unwrap().1, 6);
    assert!((measurement_sigma(&o, &key, &[0.5, 0.5], 0.0, Family::CollapseAngle).unwrap().0 - sd).abs() < 1e-12);
    // The model's spread covers the data's: zero excess.
    assert_eq!(measurement_sigma(&o, &key, &[2.0, 2.0], 0.0, Family::CollapseAngle).unwrap().0, 0.0);
    // Displacements asked for: none here.
    assert_eq!(measurement_sigma(&o, &key, &[0.5, 0.5], 0.0, Family::Displacement), None);
}
