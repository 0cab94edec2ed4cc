//! The realizations table's columns against the row's fields.

use super::*;
use serde_json::Value;

/// The keys of a row's fields as serde writes them (the column groups flat, the shaking
/// table's nested under `shake`), with their values.
fn leaves(r: &RealizationRow) -> Vec<(String, Value)> {
    let Value::Object(top) = serde_json::to_value(r).unwrap() else { panic!("a row is an object") };
    let mut out = Vec::new();
    for (k, v) in top {
        match v {
            Value::Object(inner) => out.extend(inner),
            v => out.push((k, v)),
        }
    }
    out
}

/// A row whose every field holds a value (none left out by serde).
fn full() -> RealizationRow {
    RealizationRow {
        collapse: CollapseColumns {
            collapse_angle_deg: Some(1.0),
            first_unstable_deg: Some(1.5),
            failure_height_fraction: Some(0.5),
            mechanism_extent: Some(0.25),
            ..CollapseColumns::default()
        },
        lateral: LateralColumns {
            lateral_disp_left_cm: Some(1.0),
            lateral_disp_centre_cm: Some(1.0),
            lateral_disp_right_cm: Some(1.0),
            lateral_disp_max_cm: Some(1.0),
            lateral_drift: Some(1.0),
        },
        pushover: PushoverColumns {
            load_multiplier_dem: Some(1.0),
            load_multiplier_dem_unstable: Some(1.0),
            load_multiplier_limit: Some(1.0),
        },
        in_plane: Some(Box::default()),
        compression: Some(Box::default()),
        ..RealizationRow::default()
    }
}

fn derived(c: &RowColumn) -> bool {
    matches!(c.field, Field::Derived(_))
}

/// Every field of a row (`_FIELDS` names them for the compiler) is a column of
/// [`COLUMNS`], and every column but the derived ones a field: a field added to a row
/// or to one of its column groups without its line in `COLUMNS` fails here.
#[test]
fn every_field_of_a_row_is_a_column_and_every_column_a_field() {
    let mut fields: Vec<String> = leaves(&full()).into_iter().map(|(k, _)| k).collect();
    fields.sort();
    let mut columns: Vec<String> = COLUMNS.iter().filter(|c| !derived(c)).map(|c| c.name.to_string()).collect();
    columns.sort();
    let missing: Vec<&String> = fields.iter().filter(|f| !columns.contains(f)).collect();
    let extra: Vec<&String> = columns.iter().filter(|c| !fields.contains(c)).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "fields without a column: {missing:?}; columns without a field: {extra:?}"
    );
    let mut names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), COLUMNS.len(), "a column is listed twice");
}

/// Each column writes and reads the field of its name: setting a value through the
/// column changes that field of the row and no other, and the column reads it back.
#[test]
fn each_column_reads_and_writes_the_field_of_its_name() {
    // With the in-plane and compression groups, which a value set through one of their
    // columns makes.
    let base = RealizationRow {
        in_plane: Some(Box::default()),
        compression: Some(Box::default()),
        ..RealizationRow::default()
    };
    let before = leaves(&base);
    for c in COLUMNS.iter().filter(|c| !derived(c)) {
        let mut r = base.clone();
        match c.field {
            Field::Count(get, set) => {
                set(&mut r, 7);
                assert_eq!(get(&r), 7, "{}", c.name);
            }
            Field::OptCount(get, set) => {
                set(&mut r, Some(7));
                assert_eq!(get(&r), Some(7), "{}", c.name);
            }
            Field::Text(get, set) => {
                let reason = crate::loading::tilt::CollapseReason::ALL[0].name();
                let v = ["x", "stood", reason].into_iter().find(|v| set(&mut r, v.to_string()).is_ok()).unwrap();
                assert_eq!(get(&r), v, "{}", c.name);
            }
            Field::Number(get, set) => {
                set(&mut r, 0.5);
                assert_eq!(get(&r), 0.5, "{}", c.name);
            }
            Field::OptNumber(get, set) => {
                set(&mut r, Some(0.5));
                assert_eq!(get(&r), Some(0.5), "{}", c.name);
            }
            Field::Series(get, set) => {
                *set(&mut r) = vec![0.5];
                assert_eq!(get(&r), &vec![0.5], "{}", c.name);
            }
            Field::Derived(_) => unreachable!(),
        }
        let changed: Vec<String> = leaves(&r)
            .into_iter()
            .filter(|(k, v)| before.iter().find(|(b, _)| b == k).is_none_or(|(_, w)| w != v))
            .map(|(k, _)| k)
            .collect();
        assert_eq!(changed, [c.name], "the column {} changes other fields", c.name);
    }
}
