//! The registry's tests: the seam runs each protocol as its driver runs alone, a run's
//! variant is its method, the compatibility table is whole and its copies (the doc of
//! [`super::methods`], README.md) are the registry's, the kinds' and the live loads' names.

use super::*;
use crate::layout::BaseSliding;
use crate::loading::lateral::run_lateral_penalty;
use crate::loading::tilt::run_tilt_penalty;
use crate::verify::{box_vertices, layout_of};

/// Both protocols run through the seam as their drivers run alone, bit for bit; a block
/// floating above the table is refused by either as a layout that does not stand.
#[test]
fn the_seam_runs_each_protocol_as_its_driver_runs_alone() {
    let l = layout_of(vec![box_vertices([0.0, -0.05, 0.0], [0.2, 0.05, 0.2])], 1e9, 5e8, 35.0, BaseSliding::Free);
    let tilt = TiltParams { resolution_deg: 0.5, ..TiltParams::default() };
    let ProtocolRun::Tilt(TiltRun::Penalty(Ok(a))) = Protocol::tilting(tilt).run(&l, SolverParams::default()) else {
        panic!()
    };
    let b = run_tilt_penalty(&l, SolverParams::default(), &tilt, &mut |_, _, _| {}).unwrap();
    assert_eq!((a.last_stable_deg, a.first_unstable_deg, a.steps), (b.last_stable_deg, b.first_unstable_deg, b.steps));
    let lateral = LateralParams::default();
    let ProtocolRun::Lateral(LateralRun::Penalty(Ok(c))) = Protocol::lateral(lateral).run(&l, SolverParams::default())
    else {
        panic!()
    };
    let d = run_lateral_penalty(&l, SolverParams::default(), &lateral, &mut |_, _, _| {}).unwrap();
    assert_eq!((c.displacement_m, c.steps), (d.displacement_m, d.steps));
    let floating =
        layout_of(vec![box_vertices([0.0, -0.05, 0.1], [0.2, 0.05, 0.3])], 1e9, 5e8, 35.0, BaseSliding::Free);
    for p in [Protocol::tilting(tilt), Protocol::lateral(lateral)] {
        let run = p.run(&floating, SolverParams::default());
        assert!(run.does_not_stand(), "{}: {:?}", p.name(), run.error());
        assert!(run.error().unwrap().contains("touches nothing"), "{:?}", run.error());
    }
}

/// A run's variant is the method that ran it (`TiltRun::method` and the others: their
/// variants are named as [`Method`]'s), for every method the row lists.
#[test]
fn a_runs_variant_is_the_method_that_ran_it() {
    let l = layout_of(vec![box_vertices([0.0, -0.05, 0.0], [0.2, 0.05, 0.2])], 1e9, 5e8, 35.0, BaseSliding::Free);
    let tilt = Tilt(TiltParams { resolution_deg: 0.5, ..TiltParams::default() });
    let lateral = Lateral(LateralParams::default());
    for m in Method::ALL {
        let solver = SolverParams { kind: m.kind(), ..SolverParams::default() };
        assert_eq!(run(&tilt, &l, solver, &mut ()).map(|r| r.method()), Ok(m));
        match run(&lateral, &l, solver, &mut ()) {
            Ok(r) => assert_eq!(r.method(), m),
            Err(_) => assert!(!supports(Loading::Lateral, m), "{m}"),
        }
    }
}

/// Every protocol runs by at least one method; the motions by no static cascade; every
/// refusal names the methods that do run the protocol; the names round-trip.
#[test]
fn the_table_is_whole_and_its_refusals_name_the_way() {
    for p in Loading::ALL {
        assert!(Method::ALL.into_iter().any(|m| supports(p, m)), "{p:?}");
        // Each method at most once in a row: the first would shadow the second.
        let mut row = listed(p);
        let n = row.len();
        row.sort_by_key(|m| m.name());
        row.dedup();
        assert_eq!(row.len(), n, "{p:?} lists a method twice");
        for k in SolverKind::ALL {
            match check(p, k) {
                Ok(()) => assert!(supports(p, k.method()) && !(p.is_motion() && k.names_cascade())),
                Err(e) => {
                    let text = e.to_string();
                    assert!(text.contains(p.describe()) && text.contains(k.name()), "{text}");
                    for m in Method::ALL.into_iter().filter(|&m| supports(p, m)) {
                        assert!(text.contains(m.name()), "{text}");
                    }
                }
            }
        }
    }
    assert!(check(Loading::Shake, SolverKind::Relaxation)
        .unwrap_err()
        .to_string()
        .contains("cascade of static solves"));
    assert!(check(Loading::Tilt, SolverKind::Relaxation).is_ok());
    assert!(check(Loading::TiltByHand, SolverKind::Penalty).is_err());
    assert!(check(Loading::Lateral, SolverKind::Nscd).is_err());
    assert!(check(Loading::Pushover, SolverKind::Nscd).is_ok());
    for p in Loading::ALL {
        assert_eq!(Loading::from_name(p.name()), Some(p));
    }
}

/// The compatibility table as the doc of [`methods`] and README.md show it, generated
/// from the registry: a row per protocol (its name and what it is), a column per method
/// (what it is and the solver kinds that select it), each cell what the method gives
/// ([`Way::what`]), with the kinds [`check`] admits when it admits only some.
fn table() -> Vec<String> {
    let cell = |s: &str| s.replace('|', "\\|");
    let kinds =
        |ks: &mut dyn Iterator<Item = SolverKind>| ks.map(|k| format!("`{}`", k.name())).collect::<Vec<_>>().join(", ");
    let mut header = vec!["protocol".to_string()];
    header.extend(Method::ALL.map(|m| format!("{} ({})", m.describe(), kinds(&mut m.kinds().iter().copied()))));
    let mut lines = vec![format!("| {} |", header.join(" | ")), format!("|{}", " --- |".repeat(header.len()))];
    for p in Loading::ALL {
        let mut row = vec![format!("`{}`: {}", p.name(), p.describe())];
        row.extend(Method::ALL.map(|m| match methods(p, m) {
            None => "–".to_string(),
            Some(what) => {
                let admitted: Vec<SolverKind> = m.kinds().iter().copied().filter(|&k| check(p, k).is_ok()).collect();
                if admitted.len() == m.kinds().len() {
                    cell(what)
                } else {
                    format!("{} ({} only)", cell(what), kinds(&mut admitted.into_iter()))
                }
            }
        }));
        lines.push(format!("| {} |", row.join(" | ")));
    }
    lines
}

/// The table's lines in `text`: the first run of lines that, with `prefix` and the
/// indentation before it removed, start with `| protocol |` and then `|`.
fn copy_in(text: &str, prefix: &str) -> Vec<String> {
    let strip = |l: &str| l.trim_start().strip_prefix(prefix).map(str::trim_end).map(str::to_string);
    text.lines()
        .map(strip)
        .skip_while(|l| !l.as_deref().is_some_and(|l| l.starts_with("| protocol |")))
        .take_while(|l| l.as_deref().is_some_and(|l| l.starts_with('|')))
        .flatten()
        .collect()
}

/// The copies of the compatibility table in this module's doc (of [`methods`]) and in
/// README.md are the registry's ([`LoadingProtocol::WAYS`]): a method added to a
/// protocol's row, or a protocol to the registry, fails here with the text to paste.
#[test]
fn the_table_in_the_doc_and_the_readme_is_the_registrys() {
    let expected = table();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for (file, prefix, indent) in [("src/protocol/mod.rs", "/// ", "        /// "), ("README.md", "", "  ")] {
        let text = std::fs::read_to_string(root.join(file)).unwrap();
        let copy = copy_in(&text, prefix);
        assert!(
            copy == expected,
            "the compatibility table in {file} is not the registry's; paste this in its place:\n\n{}\n",
            expected.iter().map(|l| format!("{indent}{l}")).collect::<Vec<_>>().join("\n")
        );
    }
}

/// Limit analysis's live loads (`limit::LiveLoad`, below the registry: the load with
/// its values) are spelled as the kinds whose runs give them (`protocol` of
/// `drystone limit --json`): an exhaustive match, so that a new live load is given its
/// kind here.
#[test]
fn the_live_loads_are_spelled_as_their_kinds() {
    use crate::limit::LiveLoad;
    let kind = |l: &LiveLoad| match l {
        LiveLoad::Tilt => ProtocolKind::Tilt,
        LiveLoad::Lateral { .. } => ProtocolKind::Lateral,
        LiveLoad::InPlane { .. } => ProtocolKind::InPlane,
    };
    for l in [
        LiveLoad::Tilt,
        LiveLoad::Lateral { pressure_base_pa: 1e3, pressure_top_pa: 5e2 },
        LiveLoad::InPlane { sigma0_mpa: 0.5, shear_span_m: 1.325 },
    ] {
        let v = serde_json::to_value(l).unwrap();
        let tag = match &v {
            serde_json::Value::String(s) => s.clone(),
            other => other.as_object().and_then(|o| o.keys().next().cloned()).unwrap_or_default(),
        };
        assert_eq!(tag, kind(&l).name(), "{v}");
    }
}

/// Every kind's name is its spelling in study files (serde) and on the command line
/// (`FromStr`); its rows are the protocols of its kind, the first the one its table
/// chooses by default; every protocol names its study file's kind.
#[test]
fn the_kinds_are_named_once_and_hold_their_rows() {
    for k in ProtocolKind::ALL {
        assert_eq!(toml::Value::try_from(k).unwrap().as_str(), Some(k.name()), "{k:?}");
        assert_eq!(toml::Value::String(k.name().into()).try_into::<ProtocolKind>().unwrap(), k);
        assert_eq!(k.name().parse::<ProtocolKind>(), Ok(k));
        assert!(k.loadings().iter().all(|l| l.kind() == k), "{k:?}");
    }
    assert_eq!(ProtocolKind::ALL.map(ProtocolKind::name), ["tilt", "lateral", "shake", "in_plane", "compression"]);
    assert_eq!(ProtocolKind::default(), ProtocolKind::Tilt);
    assert!("pushover".parse::<ProtocolKind>().unwrap_err().contains("tilt, lateral, shake, in_plane, compression"));
    for p in Loading::ALL {
        assert!(p.kind().loadings().contains(&p), "{p:?}");
    }
    let tilt = TiltParams::default();
    assert_eq!(Protocol::tilting(tilt).loading(), ProtocolKind::Tilt.loadings()[0]);
    assert_eq!(Protocol::lateral(LateralParams::default()).loading(), ProtocolKind::Lateral.loadings()[0]);
    for p in [Protocol::tilting(tilt), Protocol::lateral(LateralParams::default())] {
        assert_eq!(p.name(), p.loading().kind().name());
    }
}
