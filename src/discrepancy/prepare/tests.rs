//! Tests of the preparation: which effects join the default search.

use super::*;

fn names(defs: &[Arc<EffectDef>]) -> Vec<String> {
    defs.iter().map(|d| d.name.clone()).collect()
}

#[test]
fn effects_searched_by_name_only_join_the_default_search_when_a_study_adds_them() {
    let lib = effects::Library::builtin();
    let mut s = Settings::default();
    let default = names(&searched(&s, &lib, true).unwrap());
    assert!(!default.contains(&"table_kick".to_string()), "{default:?}");
    assert!(default.contains(&"leaf_split".to_string()));
    let angles_only = names(&searched(&s, &lib, false).unwrap());
    assert!(!angles_only.contains(&"leaf_split".to_string()));
    s.also_effects = vec!["table_kick".into()];
    let with = names(&searched(&s, &lib, true).unwrap());
    assert_eq!(with.len(), default.len() + 1);
    assert_eq!(with.last().map(String::as_str), Some("table_kick"));
    // Named in `effects`, the list is the search and `also_effects` is not read.
    s.effects = vec!["initial_lean".into()];
    assert_eq!(names(&searched(&s, &lib, true).unwrap()), vec!["initial_lean".to_string()]);
    s.effects.clear();
    s.also_effects = vec!["no_such_effect".into()];
    assert!(searched(&s, &lib, true).is_err());
}
