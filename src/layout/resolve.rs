//! Checking a raw [`LayoutSpec`] into a [`Layout`]: every value finite and in its range,
//! ids unique, blocks convex, materials physical, monitor points on their blocks.

use super::check::{check_convex, check_overlaps, check_own_mass};
use super::*;
use crate::units::deg_to_rad;
use std::collections::BTreeMap;

fn check_positive(key: String, v: f64) -> Result<f64, LayoutError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(invalid(key, v, "must be a finite number > 0"))
    }
}

fn check_range(key: String, v: f64, (lo, hi): (f64, f64)) -> Result<f64, LayoutError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        let value = if v != 0.0 && !(1e-3..1e7).contains(&v.abs()) { format!("{v:e}") } else { v.to_string() };
        Err(LayoutError::Invalid { key, value, reason: format!("must be in [{lo:e}, {hi:e}]") })
    }
}

fn check_non_negative(key: String, v: f64) -> Result<f64, LayoutError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(invalid(key, v, "must be a finite number >= 0"))
    }
}

impl MaterialSpec {
    /// Checks the values and converts to SI.
    ///
    /// # Errors
    /// [`LayoutError::Invalid`] naming `materials[NAME].KEY`.
    pub fn resolve(&self) -> Result<Material, LayoutError> {
        let k = |f: &str| format!("materials[{}].{}", self.name, f);
        let density = check_range(k("density_kg_per_m3"), self.density_kg_per_m3, DENSITY_RANGE_KG_PER_M3)?;
        let kn = check_range(k("kn_pa_per_m"), self.kn_pa_per_m, STIFFNESS_RANGE_PA_PER_M)?;
        let ks = check_range(k("ks_pa_per_m"), self.ks_pa_per_m, STIFFNESS_RANGE_PA_PER_M)?;
        let phi = self.friction_deg;
        if !(phi.is_finite() && (0.0..90.0).contains(&phi)) {
            return Err(invalid(k("friction_deg"), phi, "must be in [0, 90) degrees"));
        }
        let c = check_non_negative(k("cohesion_pa"), self.cohesion_pa)?;
        let t = check_non_negative(k("tensile_strength_pa"), self.tensile_strength_pa)?;
        Ok(Material {
            density,
            kn,
            ks,
            friction: deg_to_rad(phi),
            cohesion: c,
            tensile_strength: t,
            closure: self.closure.check(&k("closure")).map_err(super::joints::closure_error)?,
        })
    }
}

/// Why a joint of normal stiffness `kn` (Pa/m) is too soft under the weight of the densest
/// material `rho` (kg/m³) at `gravity` (m/s²): `Some(reason)` when it would close by more
/// than [`MAX_CLOSURE_RATIO`] of the wall's height, `ρ g H / Kn > 0.01 H`, with the Kn it
/// needs. The one rule of layout files and wall descriptions.
pub fn too_soft(rho: f64, gravity: f64, kn: f64) -> Option<String> {
    let closure = rho * gravity / kn;
    (closure > MAX_CLOSURE_RATIO).then(|| {
        format!(
            "too soft for the density and gravity: Kn = {kn:e} Pa/m closes the joints by ρ g H / Kn = {closure:.3} of \
             the wall height H under its own weight (at most {MAX_CLOSURE_RATIO}: Kn ≥ {:.3e} Pa/m here)",
            rho * gravity / MAX_CLOSURE_RATIO
        )
    })
}

/// The joints of a family may not be softer than the material rule allows
/// ([`too_soft`]) with the densest material.
fn check_family_softness(f: &JointFamilies, materials: &[Material], gravity: f64) -> Result<(), LayoutError> {
    let rho = materials.iter().map(|m| m.density).fold(0.0, f64::max);
    let kn_min = materials.iter().map(|m| m.kn).fold(f64::INFINITY, f64::min);
    for fam in JointFamily::ALL {
        let Some(fj) = f.get(fam) else { continue };
        let (kn, key, value) = match fj.kn {
            Some(kn) => (kn, "kn_pa_per_m", kn),
            None => (kn_min * fj.kn_factor, "kn_factor", fj.kn_factor),
        };
        if let Some(reason) = too_soft(rho, gravity, kn) {
            return Err(invalid(format!("joint_families.{}.{key}", fam.name()), value, &reason));
        }
    }
    Ok(())
}

impl LayoutSpec {
    /// Checks everything and builds the [`Layout`].
    ///
    /// # Errors
    /// The first problem found, naming the key or block.
    pub fn resolve(&self) -> Result<Layout, LayoutError> {
        if self.version != LAYOUT_VERSION {
            return Err(invalid("version", self.version, "this drystone reads layout version 1"));
        }
        let gravity = check_range("gravity_m_per_s2".into(), self.gravity_m_per_s2, GRAVITY_RANGE_M_PER_S2)?;
        if self.materials.is_empty() {
            return Err(invalid("materials", "[]", "at least one material is needed"));
        }
        let (materials, by_name) = self.resolve_materials(gravity)?;
        let table_material = *by_name
            .get(&self.table.material)
            .ok_or_else(|| invalid("table.material", &self.table.material, "no such material"))?;
        let (blocks, ids) = self.resolve_blocks(&by_name)?;
        if self.blocks.iter().all(|b| b.fixed) {
            return Err(invalid(
                "blocks",
                format!("{} blocks, every one fixed", self.blocks.len()),
                "no free block: nothing can move, so a test would report the tilt it stopped at as a collapse angle (set `fixed = false` on the blocks of the wall)",
            ));
        }
        check_overlaps(&blocks)?;
        let end_restraints = self.resolve_end_restraints(&ids)?;
        let ropes: Vec<_> =
            self.restraints.ropes.iter().enumerate().map(|(k, r)| r.resolve(k, &blocks)).collect::<Result<_, _>>()?;
        let densities: Vec<f64> = materials.iter().map(|m| m.density).collect();
        super::rope::check_as_built(&ropes, &blocks, &densities, gravity)?;
        let monitors = self.resolve_monitors(&ids, &blocks)?;
        let joint_families = self.joint_families.resolve("joint_families")?;
        check_family_softness(&joint_families, &materials, gravity)?;
        let layout = Layout {
            name: self.name.clone(),
            gravity,
            material_names: self.materials.iter().map(|m| m.name.clone()).collect(),
            materials,
            table_material,
            blocks,
            base_sliding: self.restraints.base_sliding,
            end_restraints,
            ropes,
            table_overshoot_deg: 0.0,
            vertical_load_rig: super::VerticalLoadRig::default(),
            monitors,
            joint_families,
        };
        layout.check_families_present("joint_families")?;
        Ok(layout)
    }

    /// The materials in SI, and their indices by name.
    fn resolve_materials(&self, gravity: f64) -> Result<(Vec<Material>, BTreeMap<String, usize>), LayoutError> {
        let mut by_name = BTreeMap::new();
        let mut materials = Vec::new();
        for (i, m) in self.materials.iter().enumerate() {
            if by_name.insert(m.name.clone(), i).is_some() {
                return Err(invalid(format!("materials[{}].name", m.name), &m.name, "duplicate material name"));
            }
            let mat = m.resolve()?;
            if let Some(reason) = too_soft(mat.density, gravity, mat.kn) {
                return Err(LayoutError::Invalid {
                    key: format!("materials[{}].kn_pa_per_m", m.name),
                    value: mat.kn.to_string(),
                    reason,
                });
            }
            materials.push(mat);
        }
        Ok((materials, by_name))
    }

    /// The blocks, each a checked convex polyhedron, and their indices by id.
    fn resolve_blocks(
        &self,
        by_name: &BTreeMap<String, usize>,
    ) -> Result<(Vec<Block>, BTreeMap<String, usize>), LayoutError> {
        if self.blocks.is_empty() {
            return Err(invalid("blocks", "[]", "at least one block is needed"));
        }
        let mut ids = BTreeMap::new();
        let mut blocks = Vec::with_capacity(self.blocks.len());
        for (i, b) in self.blocks.iter().enumerate() {
            if b.id.is_empty() {
                return Err(invalid(format!("blocks[{i}].id"), "\"\"", "block id must not be empty"));
            }
            if ids.insert(b.id.clone(), i).is_some() {
                return Err(invalid(format!("blocks[{}].id", b.id), &b.id, "duplicate block id"));
            }
            let material = *by_name
                .get(&b.material)
                .ok_or_else(|| invalid(format!("blocks[{}].material", b.id), &b.material, "no such material"))?;
            let verts: Vec<Vec3> = b.vertices.iter().map(|v| Vec3::new(v[0], v[1], v[2])).collect();
            let shape =
                ConvexBlock::from_vertices(&verts).map_err(|source| LayoutError::Block { id: b.id.clone(), source })?;
            check_convex(&b.id, &verts, &shape)?;
            let own_mass = b.own_mass.as_ref().map(|m| check_own_mass(&b.id, m, &shape)).transpose()?;
            let bed_closure = b
                .bed_closure
                .map(|c| c.check(&format!("blocks[{}].bed_closure", b.id)))
                .transpose()
                .map_err(super::joints::closure_error)?;
            blocks.push(Block {
                id: b.id.clone(),
                material,
                shape,
                fixed: b.fixed,
                course: b.course,
                wedge: b.wedge,
                own_mass,
                bed_closure,
            });
        }
        Ok((blocks, ids))
    }

    /// The end restraints, by block index.
    fn resolve_end_restraints(&self, ids: &BTreeMap<String, usize>) -> Result<Vec<(usize, EndRestraint)>, LayoutError> {
        let mut end_restraints: Vec<(usize, EndRestraint)> = Vec::new();
        for (k, e) in self.restraints.ends.iter().enumerate() {
            let r = match (e.kind, e.stiffness_n_per_m) {
                (EndRestraintKind::Rigid, None) => EndRestraint::Rigid,
                (EndRestraintKind::Rigid, Some(s)) => {
                    return Err(invalid(
                        format!("restraints.ends[{k}].stiffness_n_per_m"),
                        s,
                        "a rigid restraint takes no stiffness",
                    ))
                }
                (EndRestraintKind::Spring, Some(s)) => {
                    EndRestraint::Spring(check_positive(format!("restraints.ends[{k}].stiffness_n_per_m"), s)?)
                }
                (EndRestraintKind::Spring, None) => {
                    return Err(invalid(
                        format!("restraints.ends[{k}].stiffness_n_per_m"),
                        "missing",
                        "a spring restraint needs a stiffness in N/m",
                    ))
                }
            };
            for id in &e.blocks {
                let bi =
                    *ids.get(id).ok_or_else(|| invalid(format!("restraints.ends[{k}].blocks"), id, "no such block"))?;
                if end_restraints.iter().any(|(j, _)| *j == bi) {
                    return Err(invalid(format!("restraints.ends[{k}].blocks"), id, "block restrained twice"));
                }
                end_restraints.push((bi, r));
            }
        }
        end_restraints.sort_by_key(|(i, _)| *i);
        Ok(end_restraints)
    }

    /// The monitor points, each on or near its block.
    fn resolve_monitors(&self, ids: &BTreeMap<String, usize>, blocks: &[Block]) -> Result<Vec<Monitor>, LayoutError> {
        let mut monitors = Vec::new();
        for m in &self.monitors {
            let bi = *ids
                .get(&m.block)
                .ok_or_else(|| invalid(format!("monitors[{}].block", m.name), &m.block, "no such block"))?;
            let p = Vec3::new(m.point[0], m.point[1], m.point[2]);
            if !p.iter().all(|c| c.is_finite()) {
                return Err(invalid(format!("monitors[{}].point", m.name), format!("{:?}", m.point), "must be finite"));
            }
            let bb = blocks[bi].shape.aabb();
            let reach = MONITOR_TOLERANCE_FRACTION * bb.extent().norm();
            let outside = (bb.min - p).sup(&(p - bb.max)).sup(&Vec3::zeros()).norm();
            if outside > reach {
                return Err(invalid(
                    format!("monitors[{}].point", m.name),
                    format!("{:?}", m.point),
                    &format!(
                        "lies {outside:.3e} m outside the bounding box of block {} (at most {reach:.3e} m); \
                         points are in metres, table frame",
                        m.block
                    ),
                ));
            }
            monitors.push(Monitor { name: m.name.clone(), block: bi, point: p });
        }
        Ok(monitors)
    }
}
