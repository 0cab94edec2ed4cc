//! The built-in effect library, written as [`EffectDef`]s like a user's own.

use super::{EffectDef, ParamDef, Property, Scale, Step};
use crate::layout::JointFamily;

fn param(name: &str, unit: &str, min: f64, max: f64, scale: Scale, neutral: f64, per_course: bool) -> ParamDef {
    ParamDef { name: name.into(), unit: unit.into(), min, max, scale, neutral, range_per_course_height: per_course }
}

fn def(name: &str, description: &str, source: &str, parameters: Vec<ParamDef>, steps: Vec<Step>) -> EffectDef {
    EffectDef { name: name.into(), description: description.into(), source: source.into(), parameters, steps }
}

fn factor() -> ParamDef {
    param("factor", "-", 0.05, 2.0, Scale::Log, 1.0, false)
}

fn stiffness(family: Option<JointFamily>) -> Step {
    Step::JointFactor { family, property: Property::Stiffness, parameter: "factor".into() }
}

/// The built-in effects, in library order.
pub fn builtin() -> Vec<EffectDef> {
    let family = |f: JointFamily, what: &str| {
        def(
            &format!("{}_stiffness", f.name()),
            &format!("Kn and Ks of the {what} scaled by a factor (their ratio kept)"),
            "compliance of one joint family (Santa-Cruz et al. 2021: timber table, hand-placed beds)",
            vec![factor()],
            vec![stiffness(Some(f))],
        )
    };
    vec![
        def(
            "kn_scale",
            "plain recalibration of Kn and Ks of every joint",
            "recalibration of the joint stiffness (Santa-Cruz et al. 2021, Table 9 procedure)",
            vec![factor()],
            vec![stiffness(None)],
        ),
        family(JointFamily::Base, "joints between the table and the first course"),
        family(JointFamily::Bed, "bed joints between courses"),
        family(JointFamily::Head, "head joints within a course"),
        def(
            "joint_closure",
            "hyperbolic normal closure of rough joints: soft at low stress, stiffening as they close",
            "Bandis, Lumsden & Barton (1983), Int. J. Rock Mech. Min. Sci. 20:249; Goodman (1976)",
            vec![
                param("initial_stiffness_ratio", "-", 0.02, 1.0, Scale::Log, 1.0, false),
                param("max_closure_m", "m", 1e-4, 5e-3, Scale::Log, f64::INFINITY, true),
            ],
            vec![
                Step::JointFactor { family: None, property: Property::Kn, parameter: "initial_stiffness_ratio".into() },
                Step::Closure { family: None, law: "hyperbolic".into(), parameter: "max_closure_m".into() },
            ],
        ),
        def(
            "seating_gap",
            "uneven beds: initial gaps up to g0 that close under load",
            "uneven beds of hand-placed stones; uniform asperity heights (Greenwood & Williamson 1966)",
            vec![param("max_gap_m", "m", 0.0, 3e-3, Scale::Linear, 0.0, true)],
            vec![Step::Closure { family: None, law: "seating".into(), parameter: "max_gap_m".into() }],
        ),
        def(
            "initial_lean",
            "the wall built out of plumb by psi towards the side it falls to",
            "construction tolerance: walls out of plumb (de Felice 2011, Int. J. Archit. Herit. 5:466)",
            vec![param("lean_deg", "deg", 0.0, 3.0, Scale::Linear, 0.0, false)],
            vec![Step::Lean { parameter: "lean_deg".into() }],
        ),
        def(
            "edge_rounding",
            "every edge of every block rounded by r: pivots move inwards, head joints open at their edges",
            "rounded and crushed block edges (Mehrotra & DeJong 2018, Earthq. Eng. Struct. Dyn. 47:2661)",
            vec![param("radius_m", "m", 0.0, 0.00625, Scale::Linear, 0.0, true)],
            vec![Step::Rounding { parameter: "radius_m".into() }],
        ),
        def(
            "restraint_stiffness",
            "end restraints as springs of finite stiffness instead of rigid",
            "finite stiffness of rope end restraints (Santa-Cruz et al. 2021, SBR set-up)",
            vec![param("stiffness_n_per_m", "N/m per block", 10.0, 1e6, Scale::Log, f64::INFINITY, false)],
            vec![Step::RestraintSpring { parameter: "stiffness_n_per_m".into() }],
        ),
        def(
            "transverse_dip",
            "bed joints dipping across the thickness, uniform in [-delta, delta] per joint",
            "stones not cut to the section: bed joints dipping across the thickness (the 'slightly irregular' stones of Santa-Cruz et al. 2021)",
            vec![param("max_dip_deg", "deg", 0.0, 15.0, Scale::Linear, 0.0, false)],
            vec![Step::TransverseDip { parameter: "max_dip_deg".into() }],
        ),
        def(
            "base_restraint",
            "the first course held against rotation by stops of height h_s on the downhill side: it overturns about the stops' top edge, not its toe",
            "Santa-Cruz et al. (2021), §2.1: \"the base of the specimens was restrained with two wooden pieces, to avoid sliding failure\"",
            vec![param("stop_height_m", "m", 0.0, 0.04, Scale::Linear, 0.0, true)],
            vec![Step::BaseStop { parameter: "stop_height_m".into(), friction_deg: None }],
        ),
        // Double-faced section: delamination, then overturning of the loose leaf.
        def(
            "leaf_split",
            "the section built as two leaves tied only by friction: every block cut parallel to the faces, the loose leaf on the side the wall falls to taking the share f of the width",
            "double-faced dry stone walls (pircas): full-scale out-of-plane tests show delamination of the section, then overturning of the loose leaf (Ita, Santa-Cruz et al. 2023, Eng. Struct., doi 10.1016/j.engstruct.2023.116153); the 1:4 walls' 150 mm base of 100 mm wide pavers (Santa-Cruz et al. 2021, Table 1) needs more than one paver across; f up to 1/2: the loose leaf no wider than the other",
            vec![param("loose_leaf_fraction", "-", 0.0, 0.5, Scale::Linear, 0.0, false)],
            vec![Step::LeafSplit { parameter: "loose_leaf_fraction".into(), through_stone_every: None }],
        ),
    ]
}
