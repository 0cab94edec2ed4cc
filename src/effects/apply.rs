//! Applying effects: an [`Effect`] checked against its definition and applied to a layout
//! (its geometry, joint-law and restraint steps), the effects' random streams
//! ([`effect_rng`]) and the application of a model's effects in stage order
//! ([`apply_all`]).

use super::rope::RopeProperty;
use super::*;
use crate::layout::{EndRestraint, FamilyJoint, JointFamily, Layout};

impl Effect {
    /// A checked effect: one value per parameter, each in its range for a wall of mean
    /// course height `course_m` (m) ([`ParamDef::statable`]: the broad range scaled to the
    /// wall, or a kind's range stated as built).
    ///
    /// # Errors
    /// [`EffectError::Arity`] or [`EffectError::OutOfRange`].
    pub fn new(def: Arc<EffectDef>, values: Vec<f64>, course_m: f64) -> Result<Effect, EffectError> {
        let ps = def.params_for(course_m);
        if values.len() != ps.len() {
            return Err(EffectError::Arity {
                effect: def.name.clone(),
                expected: ps.len(),
                given: values.len(),
                names: ps.iter().map(|p| p.name.clone()).collect::<Vec<_>>().join(", "),
            });
        }
        for (p, &v) in ps.iter().zip(&values) {
            let (min, max) = p.statable();
            let tol = 1e-9 * (max - min).abs();
            if !(v.is_finite() && v >= min - tol && v <= max + tol) {
                return Err(EffectError::OutOfRange {
                    effect: def.name.clone(),
                    param: p.name.clone(),
                    value: v,
                    min,
                    max,
                    unit: p.unit.clone(),
                });
            }
        }
        Ok(Effect { def, values, search: None })
    }

    /// The effect at search coordinates `x` (∈ [0, 1], one per parameter) of its broad
    /// ranges scaled to a wall of mean course height `course_m` (m): its values are
    /// [`ParamDef::at`] of them, and a wall of a declared kind takes the values at the same
    /// coordinates in its own ranges ([`Effect::for_kind`]).
    ///
    /// # Errors
    /// [`EffectError::Arity`] or [`EffectError::OutOfRange`].
    pub fn at_search(def: Arc<EffectDef>, x: &[f64], course_m: f64) -> Result<Effect, EffectError> {
        let values = def.params_for(course_m).iter().zip(x).map(|(p, &xi)| p.at(xi)).collect();
        let mut e = Effect::new(def, values, course_m)?;
        e.search = Some(SearchPoint { x: x.to_vec(), course_m });
        Ok(e)
    }

    /// The effect as it acts on a wall of `kind`: made at a search coordinate
    /// ([`Effect::at_search`]), each parameter with a range of its own for the kind takes the
    /// value at that coordinate in it ([`ParamDef::at_for`]); otherwise (no kind, no range
    /// of the kind, an effect with stated values) unchanged.
    pub fn for_kind(&self, kind: Option<WallKind>) -> Effect {
        let (Some(s), Some(k)) = (&self.search, kind) else {
            return self.clone();
        };
        let values = self
            .def
            .params_for(s.course_m)
            .iter()
            .zip(&s.x)
            .zip(&self.values)
            .map(|((p, &x), &v)| if p.has_kind(k) { p.at_for(Some(k), x) } else { v })
            .collect();
        Effect { def: self.def.clone(), values, search: self.search.clone() }
    }

    /// The effect's name.
    pub fn name(&self) -> &str {
        &self.def.name
    }

    /// `name=v` or `name=v1:v2`.
    pub fn label(&self) -> String {
        let v: Vec<String> = self.values.iter().map(|x| format!("{x:.4e}")).collect();
        format!("{}={}", self.def.name, v.join(":"))
    }

    /// `rig` with this effect's steps on the in-plane rig's vertical-load system applied
    /// ([`Step::set_rig`], as [`Effect::apply_stage`] applies them to a layout), for a wall
    /// of declared kind `kind` ([`Effect::for_kind`], as [`realize`] maps the values).
    pub fn on_rig(
        &self,
        rig: crate::layout::VerticalLoadRig,
        kind: Option<WallKind>,
    ) -> crate::layout::VerticalLoadRig {
        let e = if kind.is_some() && self.search.is_some() { self.for_kind(kind) } else { self.clone() };
        let mut rig = rig;
        for step in e.def.steps.iter().filter(|s| s.acts_on_readings_only()) {
            step.set_rig(&mut rig, e.value(step.parameter()));
        }
        rig
    }

    fn value(&self, parameter: &str) -> f64 {
        let i = self.def.parameters.iter().position(|p| p.name == parameter).unwrap_or(0);
        self.values[i]
    }

    /// Applies the steps of one stage to the layout of one realization. `course_tops_m`
    /// are the nominal course tops of the generated wall (m; used by `transverse_dip`),
    /// `rng` the effect's stream ([`effect_rng`]).
    ///
    /// # Errors
    /// [`EffectError::Geometry`] if a transformed block is not a valid convex block.
    pub fn apply_stage(
        &self,
        stage: Stage,
        layout: &mut Layout,
        course_tops_m: &[f64],
        rng: &mut ChaCha8Rng,
    ) -> Result<(), EffectError> {
        let geometry = |(block, reason)| EffectError::Geometry { effect: self.def.name.clone(), block, reason };
        for step in self.def.steps.iter().filter(|s| s.stage() == stage) {
            let v = self.value(step.parameter());
            // A step that reshapes blocks cannot reshape a stone whose mass is its own (a
            // scanned stone's mesh): its block would no longer be the stone's hull.
            let reshapes = match step {
                Step::Lean { .. } => v != 0.0,
                Step::Rounding { .. } | Step::TransverseDip { .. } => v > 0.0,
                Step::LeafSplit { .. } => v > 0.0 && v < 1.0,
                _ => false,
            };
            if let Some(b) = layout.blocks.iter().find(|b| reshapes && b.own_mass.is_some()) {
                return Err(EffectError::OwnMass { effect: self.def.name.clone(), block: b.id.clone() });
            }
            match step {
                Step::JointFactor { family, property, .. } => joint_factor(layout, *family, *property, v),
                Step::Closure { family, law, .. } => {
                    let c = Closure::with_length(law, v).ok_or_else(|| EffectError::UnknownLaw {
                        effect: self.def.name.clone(),
                        law: law.clone(),
                        known: Closure::length_law_names().join(", "),
                    })?;
                    // A gap of zero is the linear law (the neutral value).
                    let c = if v > 0.0 { c } else { Closure::Linear };
                    set_closure(layout, *family, c);
                }
                Step::Crushing { family, .. } => {
                    // An infinite strength (the neutral value) is the linear joint.
                    let c = if v.is_finite() {
                        Closure::Crushing(crate::closure::Crushing { strength_pa: v * 1e6 })
                    } else {
                        Closure::Linear
                    };
                    set_closure(layout, *family, c);
                }
                Step::Dilatancy { family, .. } => dilate(layout, *family, v.to_radians()),
                Step::Lean { .. } => geometry::shear_out_of_plumb(layout, v.to_radians()).map_err(geometry)?,
                Step::Rounding { .. } => geometry::round_edges(layout, v).map_err(geometry)?,
                Step::TransverseDip { .. } => {
                    geometry::tilt_beds_across(layout, v.to_radians(), course_tops_m, rng).map_err(geometry)?
                }
                Step::BaseStop { friction_deg, .. } => {
                    let material = match friction_deg {
                        None => layout.table_material,
                        Some(phi) => {
                            let mut m = layout.materials[layout.table_material];
                            m.friction = phi.to_radians();
                            layout.materials.push(m);
                            layout.material_names.push(format!("{}_stop", self.def.name));
                            layout.materials.len() - 1
                        }
                    };
                    geometry::add_base_stops(layout, v, material).map_err(geometry)?
                }
                Step::LeafSplit { through_stone_every, .. } => {
                    geometry::split_leaves(layout, v, *through_stone_every).map_err(geometry)?
                }
                Step::RestraintSpring { .. } => {
                    for (_, r) in &mut layout.end_restraints {
                        *r = if v.is_finite() { EndRestraint::Spring(v) } else { EndRestraint::Rigid };
                    }
                }
                Step::RopePretension { .. } => super::rope::set_end_rope(layout, RopeProperty::Pretension, v),
                Step::RopeStiffness { .. } => super::rope::set_end_rope(layout, RopeProperty::AxialStiffness, v),
                Step::TableOvershoot { .. } => layout.table_overshoot_deg = v,
                Step::JackTilt { .. }
                | Step::RigFriction { .. }
                | Step::JackIncline { .. }
                | Step::SeriesCompliance { .. }
                | Step::LoadEccentricity { .. }
                | Step::FixedLoad { .. }
                | Step::BeamRestraint { .. } => step.set_rig(&mut layout.vertical_load_rig, v),
            }
        }
        Ok(())
    }
}

/// The family's overrides in `layout`, created neutral if absent.
fn family_mut(layout: &mut Layout, f: JointFamily) -> &mut FamilyJoint {
    layout.joint_families.0[f as usize].get_or_insert(FamilyJoint {
        kn: None,
        ks: None,
        kn_factor: 1.0,
        ks_factor: 1.0,
        friction: None,
        cohesion: None,
        tensile_strength: None,
        closure: None,
    })
}

fn scale_family(fj: &mut FamilyJoint, property: Property, v: f64, tan_phi_default: f64) {
    let (kn, ks) = match property {
        Property::Kn => (v, 1.0),
        Property::Ks => (1.0, v),
        Property::Stiffness => (v, v),
        Property::Friction => {
            let phi = fj.friction.map_or(tan_phi_default, f64::tan);
            fj.friction = Some((phi * v).atan());
            (1.0, 1.0)
        }
        Property::Cohesion => {
            fj.cohesion = fj.cohesion.map(|c| c * v);
            (1.0, 1.0)
        }
    };
    match &mut fj.kn {
        Some(k) => *k *= kn,
        None => fj.kn_factor *= kn,
    }
    match &mut fj.ks {
        Some(k) => *k *= ks,
        None => fj.ks_factor *= ks,
    }
}

fn joint_factor(layout: &mut Layout, family: Option<JointFamily>, property: Property, v: f64) {
    let tan_phi = layout.materials.iter().map(|m| m.friction.tan()).fold(f64::INFINITY, f64::min);
    match family {
        Some(f) => scale_family(family_mut(layout, f), property, v, tan_phi),
        None => {
            for m in &mut layout.materials {
                match property {
                    Property::Kn => m.kn *= v,
                    Property::Ks => m.ks *= v,
                    Property::Stiffness => {
                        m.kn *= v;
                        m.ks *= v;
                    }
                    Property::Friction => m.friction = (m.friction.tan() * v).atan(),
                    Property::Cohesion => m.cohesion *= v,
                }
            }
            // Families with values of their own scale with the rest.
            for fj in layout.joint_families.0.iter_mut().flatten() {
                match property {
                    Property::Kn | Property::Ks | Property::Stiffness => {
                        if let Some(k) = &mut fj.kn {
                            if property != Property::Ks {
                                *k *= v;
                            }
                        }
                        if let Some(k) = &mut fj.ks {
                            if property != Property::Kn {
                                *k *= v;
                            }
                        }
                    }
                    Property::Friction => fj.friction = fj.friction.map(|p| (p.tan() * v).atan()),
                    Property::Cohesion => fj.cohesion = fj.cohesion.map(|c| c * v),
                }
            }
        }
    }
}

/// Raises the friction angle of a family (or of every joint) by `i` rad, capped at
/// [`MAX_FRICTION_DEG`]; a family without its own angle starts from the smallest of the
/// materials' (the rule of [`Property::Friction`]).
fn dilate(layout: &mut Layout, family: Option<JointFamily>, i: f64) {
    let cap = MAX_FRICTION_DEG.to_radians();
    let raise = |phi: f64| (phi + i).min(cap.max(phi));
    match family {
        Some(f) => {
            let phi0 = layout.materials.iter().map(|m| m.friction).fold(f64::INFINITY, f64::min);
            let fj = family_mut(layout, f);
            fj.friction = Some(raise(fj.friction.unwrap_or(phi0)));
        }
        None => {
            for m in &mut layout.materials {
                m.friction = raise(m.friction);
            }
            for fj in layout.joint_families.0.iter_mut().flatten() {
                fj.friction = fj.friction.map(raise);
            }
        }
    }
}

fn set_closure(layout: &mut Layout, family: Option<JointFamily>, c: Closure) {
    match family {
        Some(f) => family_mut(layout, f).closure = Some(c),
        None => {
            for m in &mut layout.materials {
                m.closure = c;
            }
            for fj in layout.joint_families.0.iter_mut().flatten() {
                if fj.closure.is_some() {
                    fj.closure = Some(c);
                }
            }
        }
    }
}

/// FNV-1a of a name (a stable hash: the effect streams must not change between builds).
fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

/// The random stream of an effect in one realization of one group: a `ChaCha8Rng` seeded
/// from the master seed mixed with the group's and the effect's names, on the stream of the
/// realization ([`crate::rng::rng_for`]'s layout of streams, purpose `Effect`).
pub fn effect_rng(master: u64, realization: u64, group: &str, effect: &str) -> ChaCha8Rng {
    let key = master ^ fnv1a(group).rotate_left(17) ^ fnv1a(effect).rotate_left(41);
    crate::rng::rng_for(key, realization, crate::rng::Purpose::Effect)
}

/// Applies `effects` to a checked layout of a generated wall: every effect's layout steps,
/// then every joint-law step, then every restraint step (effects in the order given within
/// a stage), each effect with its own stream ([`effect_rng`]). A joint-law step on a family
/// the layout does not have is an error.
///
/// # Errors
/// [`EffectError::Geometry`] or [`EffectError::NoFamily`].
pub fn apply_all(
    layout: &mut Layout,
    generated: &GeneratedWall,
    group: &str,
    effects: &[Effect],
) -> Result<(), EffectError> {
    let mut rngs: Vec<ChaCha8Rng> =
        effects.iter().map(|e| effect_rng(generated.seed, generated.realization, group, e.name())).collect();
    for stage in [Stage::Layout, Stage::JointLaw, Stage::Restraints] {
        for (e, rng) in effects.iter().zip(&mut rngs) {
            e.apply_stage(stage, layout, &generated.course_tops_m, rng)?;
        }
    }
    for e in effects {
        for f in e.def.steps.iter().filter_map(Step::family) {
            if !has_family(layout, f) {
                return Err(EffectError::NoFamily { effect: e.name().to_string(), family: f.name() });
            }
        }
    }
    Ok(())
}

fn has_family(layout: &Layout, f: JointFamily) -> bool {
    let courses = || {
        let mut c: Vec<usize> = layout.blocks.iter().filter(|b| !b.wedge).filter_map(|b| b.course).collect();
        let n = c.len();
        c.sort_unstable();
        c.dedup();
        (c.len(), n)
    };
    match f {
        JointFamily::Base => true,
        JointFamily::Wedge => layout.blocks.iter().any(|b| b.wedge),
        JointFamily::Bed => layout.blocks.iter().any(|b| b.course.is_none()) || courses().0 > 1,
        JointFamily::Head => layout.blocks.iter().any(|b| b.course.is_none()) || courses().0 < courses().1,
    }
}
