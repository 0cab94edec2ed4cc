//! The built-in effect library, written as [`EffectDef`]s like a user's own, each parameter
//! with its broad plausible range and the narrower ranges of the kinds of wall
//! ([`WallKind`]), each range with its source. A source that could not be checked against
//! the publication is marked so; `estimate (reasoning: ...)` states the argument for a
//! bound no measurement gives. The table of every range is in `docs/discrepancy.md`.

use super::{EffectDef, KindRange, ParamDef, Property, Scale, Step, WallKind};

/// `x.pipe(f)` is `f(x)`: a range per finish added to a [`sourced`] parameter in place.
trait Pipe: Sized {
    fn pipe<R>(self, f: impl FnOnce(Self) -> R) -> R {
        f(self)
    }
}

impl Pipe for ParamDef {}
use crate::layout::JointFamily;

fn param(name: &str, unit: &str, min: f64, max: f64, scale: Scale, neutral: f64, per_course: bool) -> ParamDef {
    ParamDef {
        name: name.into(),
        unit: unit.into(),
        min,
        max,
        scale,
        neutral,
        range_per_course_height: per_course,
        source: String::new(),
        kinds: vec![],
    }
}

/// The broad range's source and the ranges of the two kinds (`None`: the broad range).
fn sourced(
    mut p: ParamDef,
    broad: &str,
    paver: Option<(f64, f64, &str)>,
    shaped: Option<(f64, f64, &str)>,
) -> ParamDef {
    p.source = broad.into();
    for (kind, r) in [(WallKind::ConcretePaver, paver), (WallKind::ShapedStone, shaped)] {
        if let Some((min, max, source)) = r {
            p.kinds.push(KindRange { kind, min, max, source: source.into(), as_built: false });
        }
    }
    p
}

/// `p` with the range of walls of finish `kind` (sawn or rubble stone) and its source. A
/// finish's range is the stone's surface as built, in absolute units: it does not scale with
/// the course height ([`KindRange::as_built`]).
fn finish(mut p: ParamDef, kind: WallKind, min: f64, max: f64, source: &str) -> ParamDef {
    p.kinds.push(KindRange { kind, min, max, source: source.into(), as_built: true });
    p
}

/// `p` with the ranges of sawn and of rubble stone.
fn finishes(p: ParamDef, sawn: (f64, f64, &str), rubble: (f64, f64, &str)) -> ParamDef {
    let p = finish(p, WallKind::SawnStone, sawn.0, sawn.1, sawn.2);
    finish(p, WallKind::RubbleStone, rubble.0, rubble.1, rubble.2)
}

/// Sawn faces: the source of their narrower bounds.
const SAWN: &str = "sawn faces are flat to tenths of a mm over a block and mate: dry joints of sawn stone close and slip by tenths of a mm at their strength (Lourenço, Oliveira, Roca & Orduña 2005, J. Struct. Eng. 131:1665, sawn sandstone; Vasconcelos & Lourenço 2009, Constr. Build. Mater. 23:3337, sawn granite)";

fn def(name: &str, description: &str, source: &str, parameters: Vec<ParamDef>, steps: Vec<Step>) -> EffectDef {
    EffectDef { name: name.into(), description: description.into(), source: source.into(), parameters, steps }
}

const NOT_CHECKED: &str = "the publication could not be consulted here: the bound is an estimate of its order";

/// A stiffness factor (Kn and Ks, or Kn alone).
fn factor() -> ParamDef {
    let p = sourced(
        param("factor", "-", 0.05, 2.0, Scale::Log, 1.0, false),
        "estimate (reasoning: a recalibration of the joint stiffness of Santa-Cruz et al. 2021, Table 9, itself back-analysed: from 20 times softer to twice as stiff)",
        Some((0.2, 2.0, &format!("estimate (reasoning: cast faces mate closely, so the calibrated stiffness of the cobblestones, Table 9 of Santa-Cruz et al. 2021, is not off by more than a factor 5 below; the spread of dry-joint normal stiffness measured on units of one kind, Vlachakis et al. 2023, Constr. Build. Mater. 130880; {NOT_CHECKED})"))),
        Some((0.05, 2.0, &format!("broad range (hand-dressed beds seat on a few asperities and can be far softer than a calibration; dry joints of shaped stone: Vlachakis et al. 2023, Constr. Build. Mater. 130880; {NOT_CHECKED})"))),
    );
    finishes(
        p,
        (0.2, 2.0, &format!("estimate (reasoning: {SAWN}; a stiffness estimated from such tests is not off by more than a factor 5 below; {NOT_CHECKED})")),
        (0.05, 2.0, "broad range (rubble beds bear on a few points: as soft as any calibration allows)"),
    )
}

fn stiffness(family: Option<JointFamily>) -> Step {
    Step::JointFactor { family, property: Property::Stiffness, parameter: "factor".into() }
}

/// The built-in effects, in library order: `joint_effects`, then `wall_effects`.
pub fn builtin() -> Vec<EffectDef> {
    let mut all = joint_effects();
    all.extend(wall_effects());
    all
}

/// The effects on the joints' laws: every joint's Kn and Ks, one family's, the closure
/// law, the shear stiffness and a seating gap (library order).
fn joint_effects() -> Vec<EffectDef> {
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
                finishes(
                    sourced(
                        param("initial_stiffness_ratio", "-", 0.02, 1.0, Scale::Log, 1.0, false),
                        &format!("Kni/Kn of unmated rough joints (Bandis, Lumsden & Barton 1983; {NOT_CHECKED})"),
                        Some((0.2, 1.0, "estimate (reasoning: cast faces are mated: little closure before full contact, the initial stiffness near the calibrated one)")),
                        Some((0.02, 1.0, &format!("broad range (dressed faces close as unmated rock joints: Bandis et al. 1983; dry stone joints under normal cycles: Vlachakis et al. 2023, Constr. Build. Mater. 130880; {NOT_CHECKED})"))),
                    ),
                    (0.1, 1.0, &format!("estimate (reasoning: {SAWN}: mated joints, some closure before full contact; {NOT_CHECKED})")),
                    (0.02, 1.0, "broad range (undressed faces close as unmated rock joints: Bandis et al. 1983)"),
                ),
                finishes(
                    sourced(
                        param("max_closure_m", "m", 1e-4, 5e-3, Scale::Log, f64::INFINITY, true),
                        &format!("maximum closure Vm of rough joints, tenths of a mm to mm (Bandis, Lumsden & Barton 1983; {NOT_CHECKED})"),
                        Some((1e-4, 1e-3, "estimate (reasoning: a cast face is flat to a fraction of a mm: Vm of mated joints is tenths of a mm)")),
                        Some((2e-4, 5e-3, &format!("estimate (reasoning: hand-dressed faces have mm-size asperities; Vlachakis et al. 2023; {NOT_CHECKED})"))),
                    ),
                    (1e-4, 5e-4, &format!("estimate (reasoning: {SAWN}: Vm of a tenth to half a mm; {NOT_CHECKED})")),
                    (5e-4, 5e-3, "estimate (reasoning: undressed faces seat on asperities of mm to cm; the broad range's upper bound)"),
                ),
            ],
            vec![
                Step::JointFactor { family: None, property: Property::Kn, parameter: "initial_stiffness_ratio".into() },
                Step::Closure { family: None, law: "hyperbolic".into(), parameter: "max_closure_m".into() },
            ],
        ),
        def(
            "shear_stiffness",
            "Ks of every joint scaled by a factor, Kn kept: the joints shear more (or less) than the calibration lets them",
            "shear stiffness of dry joints identified separately from the normal one (Savalle, Lourenço & Milani 2022, Appl. Sci. 12:2108; Vlachakis et al. 2023, Constr. Build. Mater. 130880); the CBL's visible shear deformation before collapse (Santa-Cruz et al. 2021, §2.2)",
            vec![sourced(
                param("factor", "-", 0.05, 2.0, Scale::Log, 1.0, false),
                &format!("estimate (reasoning: Ks/Kn of dry joints from a few hundredths to about one, Savalle, Lourenço & Milani 2022, Appl. Sci. 12:2108, and Vlachakis et al. 2023; the calibration of Santa-Cruz et al. 2021, Table 9, has Ks/Kn 0.49; {NOT_CHECKED})"),
                Some((0.1, 2.0, "estimate (reasoning: the cobblestone calibration's Ks/Kn = 0.49, Santa-Cruz et al. 2021, Table 9; a factor 0.1 brings it to 0.05, below which a mated cast joint would not hold its shear)")),
                Some((0.05, 2.0, "broad range (rough dressed faces: Ks/Kn as low as a few hundredths)")),
            ).pipe(|p| finishes(
                p,
                (0.1, 2.0, &format!("estimate (reasoning: {SAWN}: peak slips of tenths of a mm; {NOT_CHECKED})")),
                (0.05, 2.0, "broad range (rough undressed faces)"),
            ))],
            vec![Step::JointFactor { family: None, property: Property::Ks, parameter: "factor".into() }],
        ),
        def(
            "toe_crushing",
            "the faces of every joint crush at a compressive strength fc (q = min(Kn u, fc)): a rocking toe bears the vertical force on a stress block of width N / (fc t) instead of an edge",
            "toe crushing of rocking dry-joint walls in in-plane tests (Vasconcelos & Lourenço 2009, J. Struct. Eng. 135:1269: 'R, TC' at 0.5-1.25 MPa); the compression cap of interface models of dry-joint masonry (Lourenço & Rots 1997, J. Eng. Mech. 123:660)",
            vec![sourced(
                param("strength_mpa", "MPa", 5.0, 69.2, Scale::Log, f64::INFINITY, false),
                &format!("the upper bound is the granite's uniaxial compressive strength, 69.2 MPa (Vasconcelos & Lourenço 2009, the stone of their walls; the database's fc_unit_MPa); estimate (reasoning: a dry joint's edge carries a line load on a corner that spalls well below the stone's strength: down to a fourteenth of it, 5 MPa; {NOT_CHECKED})"),
                None,
                None,
            )],
            vec![Step::Crushing { family: None, parameter: "strength_mpa".into() }],
        ),
        def(
            "seating_gap",
            "uneven beds: initial gaps up to g0 that close under load",
            "uneven beds of hand-placed stones; uniform asperity heights (Greenwood & Williamson 1966)",
            vec![sourced(
                param("max_gap_m", "m", 0.0, 3e-3, Scale::Linear, 0.0, true),
                "estimate (reasoning: hand-placed stones seat on asperities of mm size; 3 mm at a 50 mm course)",
                Some((0.0, 5e-4, "estimate (reasoning: a cast paver is flat within a bed to a fraction of a mm; its thickness tolerance of a few mm tilts the whole block rather than opening gaps within a bed)")),
                Some((0.0, 3e-3, "broad range (hand-dressed beds)")),
            ).pipe(|p| finishes(
                p,
                (0.0, 3e-4, &format!("estimate (reasoning: {SAWN}: gaps within a sawn bed of at most a few tenths of a mm; {NOT_CHECKED})")),
                (0.0, 3e-3, "broad range (undressed beds seat on a few points)"),
            ))],
            vec![Step::Closure { family: None, law: "seating".into(), parameter: "max_gap_m".into() }],
        ),
    ]
}

/// The effects on the wall as built and as held: its lean, its stones' edges, its end
/// restraints and ropes, its joints' dip and dilatancy, the base's restraint, the table's
/// kick, a leaf split and the in-plane rig's vertical load (library order after
/// [`joint_effects`]).
fn wall_effects() -> Vec<EffectDef> {
    vec![
        def(
            "initial_lean",
            "the wall built out of plumb by psi towards the side it falls to",
            "construction tolerance: walls out of plumb (de Felice 2011, Int. J. Archit. Herit. 5:466)",
            vec![sourced(
                param("lean_deg", "deg", 0.0, 3.0, Scale::Linear, 0.0, false),
                &format!("construction out of plumb of dry stone walls (de Felice 2011, Int. J. Archit. Herit. 5:466; {NOT_CHECKED})"),
                Some((0.0, 1.0, "estimate (reasoning: pavers of one height stacked course on course: 5 mm out of plumb over the 375 mm wall of Santa-Cruz et al. 2021 is 0.76 deg)")),
                Some((0.0, 3.0, "broad range (de Felice 2011)")),
            )],
            vec![Step::Lean { parameter: "lean_deg".into() }],
        ),
        def(
            "edge_rounding",
            "every edge of every block rounded by r: pivots move inwards, head joints open at their edges",
            "rounded and crushed block edges (Mehrotra & DeJong 2018, Earthq. Eng. Struct. Dyn. 47:2661)",
            vec![sourced(
                param("radius_m", "m", 0.0, 0.00625, Scale::Linear, 0.0, true),
                &format!("rounded edges of stones (Mehrotra & DeJong 2018); edge rounding back-analysed for dry stone walls (Brady & Kavanagh 2002, TRL Report 550; {NOT_CHECKED})"),
                Some((0.0, 0.0025, "estimate (reasoning: cast pavers have sharp or chamfered arrises of a few mm; 2.5 mm at a 50 mm course)")),
                Some((0.0, 0.00625, &format!("broad range (hammer-dressed edges; Brady & Kavanagh 2002, TRL Report 550; {NOT_CHECKED})"))),
            ).pipe(|p| finishes(
                p,
                (0.0, 0.0025, "estimate (reasoning: sawn arrises are sharp or chip by a few mm; as cast pavers')"),
                (0.0, 0.00625, "broad range (edges as found)"),
            ))],
            vec![Step::Rounding { parameter: "radius_m".into() }],
        ),
        def(
            "restraint_stiffness",
            "end restraints as springs of finite stiffness instead of rigid",
            "finite stiffness of rope end restraints (Santa-Cruz et al. 2021, SBR set-up)",
            vec![sourced(
                param("stiffness_n_per_m", "N/m per block", 10.0, 1e6, Scale::Log, f64::INFINITY, false),
                "estimate (reasoning: from a slack rope to a nearly rigid hold; a property of the set-up, not of the stone: no range per kind)",
                None,
                None,
            )],
            vec![Step::RestraintSpring { parameter: "stiffness_n_per_m".into() }],
        ),
        end_rope(),
        def(
            "transverse_dip",
            "bed joints dipping across the thickness, uniform in [-delta, delta] per joint",
            "stones not cut to the section: bed joints dipping across the thickness (the 'slightly irregular' stones of Santa-Cruz et al. 2021)",
            vec![sourced(
                param("max_dip_deg", "deg", 0.0, 15.0, Scale::Linear, 0.0, false),
                "estimate (reasoning: the 'slightly irregular' stones of Santa-Cruz et al. 2021, §2.1; the generator's bed segments dip up to 20 deg along the wall, §4.1, a whole bed across the thickness less)",
                Some((0.0, 5.56, "the paper's geometry: prismatic pavers laid square to the battered face dip at most as the batter, atan(36.5 mm / 375 mm) = 5.56 deg (Santa-Cruz et al. 2021, Table 1: B 150 mm, b 77 mm, H 375 mm)")),
                Some((0.0, 15.0, "broad range (shaped stones are not cut to the section)")),
            )],
            vec![Step::TransverseDip { parameter: "max_dip_deg".into() }],
        ),
        def(
            "dilatant_joints",
            "rough, interlocking bed faces: the bed joints' friction angle raised by the asperity angle i (phi + i)",
            "Patton (1966), Proc. 1st ISRM Congr. 1:509 (saw-tooth joints: apparent friction phi + i); the interlocking the paper's clump model reproduced the CBL mechanism with (Santa-Cruz et al. 2021, §5.2-5.3)",
            vec![sourced(
                param("asperity_deg", "deg", 0.0, 20.0, Scale::Linear, 0.0, false),
                &format!("asperity angles of rough joints (Patton 1966, saw-tooth tests; {NOT_CHECKED}); 20 deg a coarse interlocking face"),
                Some((0.0, 5.0, "estimate (reasoning: cast faces flat to about 1 mm over the 100 mm paver width; the interlocking of neighbouring pavers set a few mm apart in height: a few degrees)")),
                Some((0.0, 20.0, &format!("broad range (apparent friction of pairs of natural stones in tilt tests, Costa et al. 2024, Buildings 14:3744; {NOT_CHECKED})"))),
            )],
            vec![Step::Dilatancy { family: Some(JointFamily::Bed), parameter: "asperity_deg".into() }],
        ),
        def(
            "base_restraint",
            "the first course held against rotation by stops of height h_s on the downhill side: it overturns about the stops' top edge, not its toe",
            "Santa-Cruz et al. (2021), §2.1: \"the base of the specimens was restrained with two wooden pieces, to avoid sliding failure\"",
            vec![sourced(
                param("stop_height_m", "m", 0.0, 0.04, Scale::Linear, 0.0, true),
                "estimate (reasoning: the wooden pieces of Santa-Cruz et al. 2021, §2.1, are of unstated height; up to 0.8 of a 50 mm course. A property of the set-up: no range per kind)",
                None,
                None,
            )],
            vec![Step::BaseStop { parameter: "stop_height_m".into(), friction_deg: None }],
        ),
        def(
            "table_kick",
            "the table rolled by hand: every 5-degree stop kicks the wall downhill as much as an extra inclination would, so a wall whose static limit lies within that of a stop collapses at the stop",
            "Santa-Cruz et al. (2021), section 2.1-2.2: a platform on \"a semicircle wooden piece that rolls manually, controlled by a lever and pulley\", tilted \"in increments of 5 deg\" and stopped to read; a stop of peak angular deceleration a pushes a block at height z above the rolling axis downhill by a (z + d) (loading::tilt_hand, the dynamic run this quasi-static equivalent stands for)",
            vec![sourced(
                param("overshoot_deg", "deg", 0.0, 2.5, Scale::Linear, 0.0, false),
                "the dynamic run of the kicks (drystone tilt --solver nscd --by-hand, 1-degree increments) on the paper's CBL and SBL walls: stops of a table rolled at 2.5-5 deg/s that take 0.1-0.05 s (estimates: the paper gives no rate) push as hard as 1.35-5.4 deg of extra inclination at the centroid, 0.53 m above the axis of a semicircle of the platform's half width, and overshoot by 0.14-1.14 and 1.14-2.14 deg (CBL), 0.98-1.98 deg (SBL, the stronger stop): the walls collapsed at the first stop within that of their static limit. 2.5 deg: the strongest stop's bracket rounded up. A property of the set-up: no range per kind",
                None,
                None,
            )],
            vec![Step::TableOvershoot { parameter: "overshoot_deg".into() }],
        ),
        // Double-faced section: delamination, then overturning of the loose leaf.
        def(
            "leaf_split",
            "the section built as two leaves tied only by friction: every block cut parallel to the faces, the loose leaf on the side the wall falls to taking the share f of the width",
            "double-faced dry stone walls (pircas): full-scale out-of-plane tests show delamination of the section, then overturning of the loose leaf (Ita, Santa-Cruz et al. 2023, Eng. Struct., doi 10.1016/j.engstruct.2023.116153); the 1:4 walls' 150 mm base of 100 mm wide pavers (Santa-Cruz et al. 2021, Table 1) needs more than one paver across; f up to 1/2: the loose leaf no wider than the other",
            vec![sourced(
                param("loose_leaf_fraction", "-", 0.0, 0.5, Scale::Linear, 0.0, false),
                "geometry: from one leaf (f = 0) to two leaves of equal width (f = 1/2, the loose leaf no wider \
                 than the other); how the 1:4 sections were built is not stated (Santa-Cruz et al. 2021, Table 1): \
                 no range per kind",
                None,
                None,
            )],
            vec![Step::LeafSplit { parameter: "loose_leaf_fraction".into(), through_stone_every: None }],
        ),
        ]
        .into_iter()
        .chain(rig_effects())
        .collect()
}

/// The in-plane rig's effects, after the wall's in library order: its vertical jacks' tilt,
/// their bearing's friction and their incline, a compliance in series with the wall, the
/// vertical load's eccentricity, a vertical load fixed in space, and the beam's partial
/// rotational restraint, each with its range and its reasoning from the test's set-up.
fn rig_effects() -> Vec<EffectDef> {
    vec![
        // The in-plane rig's vertical load: what the horizontal actuator carries besides
        // the wall's shear.
        def(
            "jack_tilt",
            "the in-plane rig's vertical load applied by a jack (or tie rods) hinged at a distance L from the loading beam: as the beam moves by u the jack leans by u/L, and its force N pulls the beam back by N u/L, which the horizontal actuator carries on top of the wall's shear",
            "statics of a force applied between two hinges (a pendulum): a vertical jack or tie rod of length L whose end follows the beam's displacement u is inclined by u/L; shear-compression rigs apply the vertical load by jacks against a reaction frame or by rods to the strong floor, and the rig of the granite walls is not described in the data (Vanin et al. 2017 database; Vasconcelos & Lourenço 2009) in enough detail to fix L",
            vec![sourced(
                param("inverse_length_per_m", "1/m", 0.0, 1.0, Scale::Linear, 0.0, false),
                "estimate (reasoning: from 0, a load that does not lean (a jack on rollers, or hinges far apart), to 1/m, hinges 1 m apart: a jack and its load cell between a reaction frame and the beam, or rods from the floor beside a wall about 1.2 m high, are at least that long. A property of the set-up, not of the stone: no range per kind)",
                None,
                None,
            )],
            vec![Step::JackTilt { parameter: "inverse_length_per_m".into() }],
        ),
        def(
            "rig_friction",
            "the in-plane rig's vertical load bearing on the loading beam through rollers or a sliding bearing of friction coefficient mu_r: the bearing resists the beam's motion by mu_r N, which the horizontal actuator carries on top of the wall's shear",
            "Coulomb friction of the bearing that lets the beam move under the vertical load (steel rollers, PTFE sliding bearings); the rig of the granite walls is not described in the data (Vanin et al. 2017 database; Vasconcelos & Lourenço 2009) in enough detail to fix it",
            vec![sourced(
                param("friction", "-", 0.0, 0.05, Scale::Linear, 0.0, false),
                &format!("estimate (reasoning: rolling friction of steel rollers of a few thousandths up to a PTFE sliding bearing at low pressure or a worn bearing, about 0.05; {NOT_CHECKED}. A property of the set-up: no range per kind)"),
                None,
                None,
            )],
            vec![Step::RigFriction { parameter: "friction".into() }],
        ),
        def(
            "jack_incline",
            "the in-plane rig's vertical load leaning by beta in the wall's plane: its horizontal part N tan(beta) pushes the loading beam towards -x, so the actuator reads that much more pushing (+x) and as much less pulling (-x): the two directions' peaks differ by 2 N tan(beta)",
            "statics of an inclined force: a jack or tie rods set out of plumb, or a reaction frame that deflects under the vertical load; the rig of the granite walls is not described in the data (Vanin et al. 2017 database; Vasconcelos & Lourenco 2009) in enough detail to fix it",
            vec![sourced(
                param("tangent", "-", -0.03, 0.03, Scale::Linear, 0.0, false),
                "estimate (reasoning: a jack set plumb by eye, or rods to the floor, within 1-2 deg (tan 0.017-0.035) of the vertical, and a reaction frame's sway under the vertical load; +-0.03 (1.7 deg) covers the common rigs, which the data do not describe. A property of the set-up: no range per kind)",
                None,
                None,
            )],
            vec![Step::JackIncline { parameter: "tangent".into() }],
        ),
        def(
            "series_compliance",
            "a compliance c in series with the in-plane test's wall, between the measuring point and the wall: the bedding of the wall's base on its foundation and of the loading beam, slack in the actuator's pins, a measuring frame that deflects; the displacement read is the beam's own plus c V",
            "a displacement transducer referenced to the reaction frame or the strong floor reads every compliance between its reference and the beam (Vanin et al. 2017 database: the measuring point is not reported; Vasconcelos & Lourenco 2009 do not describe the reference); the measured pre-peak branch of the granite walls is nearly linear at 12-15 kN/mm to 4 mm (data/inplane_granite/curves)",
            vec![sourced(
                param("compliance_mm_per_kn", "mm/kN", 0.0, 0.1, Scale::Linear, 0.0, false),
                "estimate (reasoning: reaction frames and actuator mounts of wall tests are 10-100 kN/mm stiff or more, 0.01-0.1 mm/kN, and a dry base bedding on a levelling layer or pins with a few tenths of a mm of play add as much at forces of tens of kN; 0.1 mm/kN covers the common rigs, which the data do not describe. A property of the set-up: no range per kind)",
                None,
                None,
            )],
            vec![Step::SeriesCompliance { parameter: "compliance_mm_per_kn".into() }],
        ),
        def(
            "load_eccentricity",
            "the in-plane rig's vertical load applied e0 along the wall from the loading beam's centroid: a moment e0 P on the beam, which helps the wall's rocking one way and resists it the other (the two directions' rocking capacities differ by 2 e0 P / H0)",
            "statics of an eccentric vertical load on a beam free to rotate (Vasconcelos & Lourenco 2009: the top beam free to rotate, the vertical load kept constant); where the jack or the spreader beam bears is not given in the data",
            vec![sourced(
                param("eccentricity_m", "m", -0.05, 0.05, Scale::Linear, 0.0, false),
                "estimate (reasoning: a jack or a spreader beam centred by eye on a wall about 1 m long: within a few cm; +-5 cm, L/20 of the granite walls, covers the common rigs. A property of the set-up: no range per kind)",
                None,
                None,
            )],
            vec![Step::LoadEccentricity { parameter: "eccentricity_m".into() }],
        ),
        def(
            "fixed_vertical_load",
            "the in-plane rig's vertical load does not follow the loading beam: its point lags the beam by the share kappa of its displacement (1: it stays where it was, a jack fixed to the reaction frame bearing on the beam through rollers), so the load's sway no longer takes away the wall's capacity as the wall drifts",
            "statics of a vertical load applied through rollers from a fixed frame, against one applied by rods hinged on the beam or by dead weights that move with it; shear-compression rigs are built both ways (Vanin et al. 2017, the database's test set-ups), and the rig of the granite walls is not described in the data in enough detail to tell which",
            vec![sourced(
                param("share", "-", 0.0, 1.0, Scale::Linear, 0.0, false),
                "geometry: from a load that follows the beam (0) to one fixed in space (1); the data do not say which. A property of the set-up: no range per kind",
                None,
                None,
            )],
            vec![Step::FixedLoad { parameter: "share".into() }],
        ),
        def(
            "beam_restraint",
            "the in-plane test's loading beam partly restrained against rotation in the wall's plane by a spring K_theta: two vertical jacks that do not share one pressure, guides, a beam held by the frame",
            "statics of a rotational spring on the beam between the test's two ideal cases, the beam free (cantilever, the granite walls' stated set-up: Vasconcelos & Lourenco 2009) and held (double curvature)",
            vec![sourced(
                param("stiffness_mnm_per_rad", "MN m/rad", 0.0, 5.0, Scale::Linear, 0.0, false),
                "estimate (reasoning: 0, one jack on a hinge or two on one pressure line, the stated free beam, to 5 MN m/rad, which at 1 % rotation carries 50 kN m, half the rocking moment N L of a 1 m wall under 100 kN: a restraint as strong as the wall's own; the common rigs lie between. A property of the set-up: no range per kind)",
                None,
                None,
            )],
            vec![Step::BeamRestraint { parameter: "stiffness_mnm_per_rad".into() }],
        ),
    ]
}

/// `end_rope`: the end restraints replaced by a tensioned rope at each end
/// ([`super::rope`]; docs/rope.md gives the law, the geometry and the ranges' sources).
fn end_rope() -> EffectDef {
    def(
        "end_rope",
        "rigid ends replaced by a tension-only rope at each end (pretension T0, axial stiffness EA) bearing on the \
         wall's face over its height: the wall spans between the ropes",
        "Santa-Cruz et al. (2021), §2.1: \"a rope manually tensioned at the specimen ends\", 1.4 m apart. Ranges are \
         estimates: T0 50-1500 N, a hand pull of 0.1-0.5 kN, up to about 1.5 kN with a tensioning hitch; EA 1e4-2e5 N, \
         6-10 mm polypropylene or nylon rope, EA taken as the makers' minimum breaking load (about 6-20 kN) over the \
         strain at break (about 0.15-0.3), stiffer in the working range",
        vec![
            sourced(
                param("pretension_n", "N", 50.0, 1500.0, Scale::Log, f64::INFINITY, false),
                "estimate (reasoning: a hand pull of 0.1-0.5 kN, up to about 1.5 kN with a tensioning hitch; a \
                 property of the set-up, not of the stone: no range per kind)",
                None,
                None,
            ),
            sourced(
                param("axial_stiffness_n", "N", 1e4, 2e5, Scale::Log, f64::INFINITY, false),
                "estimate (reasoning: 6-10 mm polypropylene or nylon rope, the makers' minimum breaking load of \
                 about 6-20 kN over the strain at break of about 0.15-0.3; no range per kind)",
                None,
                None,
            ),
        ],
        vec![
            Step::RopePretension { parameter: "pretension_n".into() },
            Step::RopeStiffness { parameter: "axial_stiffness_n".into() },
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every parameter has a source for its broad range and for each kind's, every kind's
    /// range passes the check an effect file's would, and the search coordinate of the
    /// neutral value is the neutral value for every kind.
    #[test]
    fn every_range_has_its_source_and_keeps_the_neutral_point() {
        for d in builtin() {
            for p in &d.parameters {
                assert!(!p.source.is_empty(), "{}.{}", d.name, p.name);
                p.check_kinds().unwrap_or_else(|e| panic!("{}.{}: {e}", d.name, p.name));
                let xn = p.position(p.neutral).clamp(0.0, 1.0);
                for r in &p.kinds {
                    assert!(!r.source.is_empty(), "{}.{} {:?}", d.name, p.name, r.kind);
                    assert_eq!(p.at_for(Some(r.kind), 0.0), r.min);
                    assert!((p.at_for(Some(r.kind), 1.0) - r.max).abs() <= 1e-12 * r.max.abs());
                    if p.neutral.is_finite() {
                        let v = p.at_for(Some(r.kind), xn);
                        assert!((v - p.neutral).abs() <= 1e-12, "{}.{}: {v} at the neutral point", d.name, p.name);
                    }
                }
            }
        }
    }

    /// The CBL bound is the batter's angle: atan(36.5/375) in degrees to the two decimals
    /// written.
    #[test]
    fn the_paver_dip_is_the_batter_angle() {
        let d = builtin().into_iter().find(|d| d.name == "transverse_dip").unwrap();
        let (_, max, _) = d.parameters[0].range_for(Some(WallKind::ConcretePaver));
        let batter = (0.5 * (0.150 - 0.077) / 0.375_f64).atan().to_degrees();
        assert!((max - batter).abs() < 0.005, "{max} vs {batter}");
    }

    /// The built-ins the in-plane test does not read are the out-of-plane set-up's, as the
    /// in-plane study's own list of what it searches states (`studies/inplane_granite.toml`:
    /// lean, end restraints and ropes, base stops, leaf split, transverse dip, the table's
    /// kick); the rig's vertical load and the joints' law are read.
    #[test]
    fn the_in_plane_test_does_not_read_the_out_of_plane_set_ups_effects() {
        let mut not_read: Vec<String> =
            builtin().into_iter().filter(|d| d.not_read_in_plane().is_some()).map(|d| d.name).collect();
        not_read.sort();
        let mut want = [
            "base_restraint",
            "end_rope",
            "initial_lean",
            "leaf_split",
            "restraint_stiffness",
            "table_kick",
            "transverse_dip",
        ];
        want.sort();
        assert_eq!(not_read, want);
    }

    /// A finish's range is the stone's surface as built: on the granite walls' 0.15 m courses
    /// (three times the reference course height) the sawn stone's maximum closure is searched
    /// on [0.1, 0.5] mm as its reasoning states, where a model-scale kind's range and the
    /// broad range scale with the course; a value in the sawn range can be stated on any
    /// wall, and a value outside every range cannot.
    #[test]
    fn a_finishs_range_is_as_built_and_a_model_scale_kinds_scales() {
        let d = builtin().into_iter().find(|d| d.name == "joint_closure").unwrap();
        let course = 3.0 * crate::effects::REFERENCE_COURSE_HEIGHT_M;
        let vm = d.parameters[1].for_course_height(course);
        let (lo, hi, _) = vm.range_for(Some(WallKind::SawnStone));
        assert_eq!((lo, hi), (1e-4, 5e-4));
        let (lo, hi, _) = vm.range_for(Some(WallKind::ConcretePaver));
        assert!((lo - 3e-4).abs() < 1e-15 && (hi - 3e-3).abs() < 1e-15, "[{lo}, {hi}]");
        assert!((vm.min - 3e-4).abs() < 1e-15, "{}", vm.min);
        assert_eq!(vm.statable().0, 1e-4);
        let def = std::sync::Arc::new(d);
        assert!(crate::effects::Effect::new(def.clone(), vec![1.0, 1e-4], course).is_ok());
        assert!(crate::effects::Effect::new(def, vec![1.0, 5e-5], course).is_err());
    }
}
