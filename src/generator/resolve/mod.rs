//! From the wall description as written ([`WallSpec`]) to the checked [`Wall`]: one
//! function per section of the file, each checking its keys in file order and filling in
//! the defaults of the [module doc](super). The first problem found is the error; every
//! error names the file and the key.

mod section;
mod values;

use super::distribution::{valid_name, Distribution, DistributionSource, Unit};
use super::spec::{
    ArrangementKind, DistRef, EndKind, WallSpec, DEFAULT_DIP_DEG, DEFAULT_MIN_END_FRACTION,
    DEFAULT_MIN_THICKNESS_FRACTION, DEFAULT_MIN_WEDGE_LENGTH_FRACTION, DEFAULT_MIN_WEDGE_THICKNESS_FRACTION,
    DEFAULT_OVERLAP, WALL_VERSION,
};
use super::wall::{Arrangement, Ends, HeadGap, Irregular, Scatter, Wall};
use super::GeneratorError;
use std::collections::BTreeSet;
use std::path::Path;

/// The thinnest leaf, hearting and hearting piece a double-faced section may have, m
/// (`section.leaf_width_m`, the hearting's width at the top, `section.hearting_stone_m`):
/// twice the solvers' default contact margin (1 mm), so that the two faces of a piece are
/// told apart by contact detection. Thinner pieces are slivers no solver resolves.
pub const MIN_SECTION_PIECE_M: f64 = 2e-3;

impl Wall {
    /// Reads and checks a wall file, finding named distributions with
    /// [`DistributionSource::default_for`].
    ///
    /// # Errors
    /// Any [`GeneratorError`], naming the file and key.
    pub fn from_file(path: &Path) -> Result<Wall, GeneratorError> {
        Self::from_file_with(path, &DistributionSource::default_for(path))
    }

    /// Reads and checks a wall file with an explicit distribution source.
    ///
    /// # Errors
    /// Any [`GeneratorError`], naming the file and key.
    pub fn from_file_with(path: &Path, source: &DistributionSource) -> Result<Wall, GeneratorError> {
        let text =
            std::fs::read_to_string(path).map_err(|e| GeneratorError::Io { path: path.to_owned(), source: e })?;
        WallSpec::from_toml(&text, path)?.resolve(path, source)
    }

    /// Every distribution of the wall: its course height and block length, an irregular
    /// wall's dip and wedge length, its scatter's Kn factor, friction offset and bed seating
    /// gap (the files
    /// a study records as its inputs).
    pub fn distributions(&self) -> Vec<&super::Distribution> {
        let mut v = vec![&self.course_height, &self.block_length];
        if let super::Arrangement::Irregular(ir) = &self.arrangement {
            v.push(&ir.dip);
            v.extend(ir.wedge_length.as_ref());
        }
        if let Some(s) = &self.scatter {
            v.extend(s.kn_factor.as_ref());
            v.extend(s.friction_offset.as_ref());
            v.extend(s.bed_seating_gap.as_ref());
        }
        if let Some(t) = &self.traced {
            v.extend(t.depth.as_ref());
        }
        v
    }
}

impl WallSpec {
    /// Checks every value and builds the [`Wall`]. `path` names the file in errors;
    /// `source` finds named distributions.
    ///
    /// # Errors
    /// The first problem found, as [`GeneratorError::Invalid`] or
    /// [`GeneratorError::UnknownDistribution`] naming `path` and the key.
    pub fn resolve(&self, path: &Path, source: &DistributionSource) -> Result<Wall, GeneratorError> {
        let r = Resolver { spec: self, path, source };
        if self.version != WALL_VERSION {
            return Err(r.invalid("version", self.version.to_string(), "this drystone reads wall version 1"));
        }
        let gravity = r.positive("gravity_m_per_s2", self.gravity_m_per_s2)?;
        let envelope = r.geometry()?;
        let (course_height, min_thickness_fraction) = r.courses(envelope.height)?;
        let (block_length, min_end_fraction) = r.blocks(envelope.length)?;
        let arrangement = r.arrangement(&course_height, &block_length)?;
        let head_gap = r.head_joints(&block_length, min_end_fraction)?;
        let [block_material, wedge_material, table_material] = r.materials()?;
        let ends = r.ends(envelope.length)?;
        let scatter = r.scatter()?;
        r.joints(&arrangement)?;
        r.softness(gravity)?;
        r.inline_distributions()?;
        let section = r.section(&envelope)?;

        Ok(Wall {
            name: if self.name.is_empty() {
                path.file_stem().and_then(|s| s.to_str()).unwrap_or("wall").to_string()
            } else {
                self.name.clone()
            },
            source: path.to_owned(),
            gravity,
            length: envelope.length,
            height: envelope.height,
            base_width: envelope.base_width,
            top_width: envelope.top_width,
            batter: self.geometry.batter,
            arrangement,
            course_height,
            min_thickness_fraction,
            block_length,
            min_end_fraction,
            head_gap,
            materials: self.materials.clone(),
            block_material,
            wedge_material,
            table_material,
            base: self.restraints.base,
            ends,
            scatter,
            joints: self.joints.clone(),
            kind: self.kind,
            section,
            traced: None,
        })
    }
}

/// The checked `[geometry]`: L, H, B, b in m.
struct Envelope {
    length: f64,
    height: f64,
    base_width: f64,
    top_width: f64,
}

/// The wall description being checked, the file it came from (for messages) and where named
/// distributions are found.
struct Resolver<'a> {
    spec: &'a WallSpec,
    path: &'a Path,
    source: &'a DistributionSource,
}

/// How a value was given, for messages: the number, or the name and the law.
fn describe(r: &DistRef, d: &Distribution) -> String {
    match r {
        DistRef::Value(v) => v.to_string(),
        DistRef::Name(n) => format!("{n:?} ({:?})", d.law),
    }
}

/// Sections of the file, in the order they are checked.
impl Resolver<'_> {
    /// `[geometry]`: positive dimensions, b ≤ B.
    fn geometry(&self) -> Result<Envelope, GeneratorError> {
        let g = &self.spec.geometry;
        let length = self.positive("geometry.length_m", g.length_m)?;
        let height = self.positive("geometry.height_m", g.height_m)?;
        let base_width = self.positive("geometry.base_width_m", g.base_width_m)?;
        let top_width = self.positive("geometry.top_width_m", g.top_width_m)?;
        if top_width > base_width {
            return Err(self.invalid(
                "geometry.top_width_m",
                top_width.to_string(),
                format!("must not exceed geometry.base_width_m = {base_width} (b ≤ B)"),
            ));
        }
        Ok(Envelope { length, height, base_width, top_width })
    }

    /// `[courses]`: the course height law (mean ≤ H) and the thinnest stone fraction.
    fn courses(&self, height: f64) -> Result<(Distribution, f64), GeneratorError> {
        let c = &self.spec.courses;
        let course_height = self.size_law(&c.height_m, "courses.height_m", "course height", "wall height H", height)?;
        let min_thickness_fraction = self.fraction(
            "courses.min_thickness_fraction",
            c.min_thickness_fraction.unwrap_or(DEFAULT_MIN_THICKNESS_FRACTION),
            false,
            false,
        )?;
        Ok((course_height, min_thickness_fraction))
    }

    /// `[blocks]` (lengths): the block length law (mean ≤ L) and the shortest end piece.
    fn blocks(&self, length: f64) -> Result<(Distribution, f64), GeneratorError> {
        let b = &self.spec.blocks;
        let block_length = self.size_law(&b.length_m, "blocks.length_m", "block length", "wall length L", length)?;
        let min_end_fraction = self.fraction(
            "blocks.min_end_fraction",
            b.min_end_fraction.unwrap_or(DEFAULT_MIN_END_FRACTION),
            false,
            true,
        )?;
        Ok((block_length, min_end_fraction))
    }

    /// `[arrangement]`: the keys of the other kinds are rejected; continuous and
    /// discontinuous walls need a fixed block length.
    fn arrangement(
        &self,
        course_height: &Distribution,
        block_length: &Distribution,
    ) -> Result<Arrangement, GeneratorError> {
        let a = &self.spec.arrangement;
        let kind_name = a.kind.name();
        let only = |key: &str, given: bool, for_kind: &str| -> Result<(), GeneratorError> {
            if given {
                Err(self.invalid(
                    &format!("arrangement.{key}"),
                    "(given)".into(),
                    format!("only for kind = \"{for_kind}\", not \"{kind_name}\""),
                ))
            } else {
                Ok(())
            }
        };
        match a.kind {
            ArrangementKind::Continuous | ArrangementKind::Discontinuous => {
                only("dip_deg", a.dip_deg.is_some(), "irregular")?;
                only("min_wedge_thickness_m", a.min_wedge_thickness_m.is_some(), "irregular")?;
                only("min_wedge_length_m", a.min_wedge_length_m.is_some(), "irregular")?;
                only("wedge_length_m", a.wedge_length_m.is_some(), "irregular")?;
                only("wedge_fill", a.wedge_fill.is_some(), "irregular")?;
                if !block_length.is_fixed() {
                    return Err(self.invalid(
                        "blocks.length_m",
                        describe(&self.spec.blocks.length_m, block_length),
                        format!("the {kind_name} arrangement needs a fixed block length (a number)"),
                    ));
                }
                if a.kind == ArrangementKind::Continuous {
                    only("overlap", a.overlap.is_some(), "discontinuous")?;
                    Ok(Arrangement::Continuous)
                } else {
                    let overlap =
                        self.fraction("arrangement.overlap", a.overlap.unwrap_or(DEFAULT_OVERLAP), false, false)?;
                    Ok(Arrangement::Discontinuous { overlap })
                }
            }
            ArrangementKind::Irregular => {
                only("overlap", a.overlap.is_some(), "discontinuous")?;
                let irregular = self.irregular(course_height.mean(), block_length.mean())?;
                Ok(Arrangement::Irregular(Box::new(irregular)))
            }
        }
    }

    /// The irregular arrangement's keys: the dip law (inside (−90°, 90°)) and the wedges.
    /// `h_mean` and `l_mean` (m) scale the default thinnest and narrowest wedge.
    fn irregular(&self, h_mean: f64, l_mean: f64) -> Result<Irregular, GeneratorError> {
        let a = &self.spec.arrangement;
        let dip = match &a.dip_deg {
            Some(r) => self.dist(r, "arrangement.dip_deg", Unit::Deg)?,
            None => Distribution::uniform("default_dip", DEFAULT_DIP_DEG.0, DEFAULT_DIP_DEG.1, Unit::Deg),
        };
        let (lo, hi) = dip.support();
        if !(lo > -90.0 && hi < 90.0) {
            return Err(self.invalid(
                "arrangement.dip_deg",
                describe(a.dip_deg.as_ref().unwrap_or(&DistRef::Value(lo)), &dip),
                format!(
                    "dips range over [{lo}, {hi}] degrees; they must lie inside (-90, 90) \
                     (use a bounded law: uniform, truncated_normal or fixed)"
                ),
            ));
        }
        let min_wedge_thickness = match a.min_wedge_thickness_m {
            Some(v) => self.nonneg("arrangement.min_wedge_thickness_m", v)?,
            None => DEFAULT_MIN_WEDGE_THICKNESS_FRACTION * h_mean,
        };
        let min_wedge_length = match a.min_wedge_length_m {
            Some(v) => self.nonneg("arrangement.min_wedge_length_m", v)?,
            None => DEFAULT_MIN_WEDGE_LENGTH_FRACTION * l_mean,
        };
        let wedge_length = match &a.wedge_length_m {
            Some(r) => {
                let d = self.dist(r, "arrangement.wedge_length_m", Unit::M)?;
                self.positive_support(&d, "arrangement.wedge_length_m")?;
                Some(d)
            }
            None => None,
        };
        let wedge_fill = self.fraction("arrangement.wedge_fill", a.wedge_fill.unwrap_or(1.0), true, true)?;
        Ok(Irregular { dip, min_wedge_thickness, min_wedge_length, wedge_length, wedge_fill })
    }

    /// `[head_joints]`: at most one of a micro-gap (narrower than half the shortest block
    /// piece) and a void fraction in [0, 0.5); zero is closed.
    fn head_joints(&self, block_length: &Distribution, min_end_fraction: f64) -> Result<HeadGap, GeneratorError> {
        let hj = &self.spec.head_joints;
        match (hj.micro_gap_m, hj.void_fraction) {
            (Some(_), Some(_)) => Err(self.invalid(
                "head_joints.void_fraction",
                "(given)".into(),
                "give either head_joints.micro_gap_m or head_joints.void_fraction, not both",
            )),
            (Some(w), None) => {
                let w = self.nonneg("head_joints.micro_gap_m", w)?;
                let (lmin, _) = block_length.support();
                let shortest = (min_end_fraction * block_length.mean()).min(lmin.max(0.0).max(1e-300));
                if w >= 0.5 * shortest {
                    return Err(self.invalid(
                        "head_joints.micro_gap_m",
                        w.to_string(),
                        format!("must be smaller than half the shortest block piece ({shortest} m)"),
                    ));
                }
                Ok(if w == 0.0 { HeadGap::Closed } else { HeadGap::Width(w) })
            }
            (None, Some(f)) => {
                if !(f.is_finite() && (0.0..0.5).contains(&f)) {
                    return Err(self.invalid("head_joints.void_fraction", f.to_string(), "must be in [0, 0.5)"));
                }
                Ok(if f == 0.0 { HeadGap::Closed } else { HeadGap::VoidFraction(f) })
            }
            (None, None) => Ok(HeadGap::Closed),
        }
    }

    /// `[[materials]]` (at least one, unique names without `~`, each valid as in a layout
    /// file) and the material names of the stones, the wedges and the table joint.
    fn materials(&self) -> Result<[String; 3], GeneratorError> {
        let materials = &self.spec.materials;
        if materials.is_empty() {
            return Err(self.invalid("materials", "[]".into(), "at least one material is needed"));
        }
        let mut names = BTreeSet::new();
        for m in materials {
            let key = format!("materials[{}].name", m.name);
            if !names.insert(m.name.clone()) {
                return Err(self.invalid(&key, m.name.clone(), "duplicate material name"));
            }
            if m.name.contains('~') {
                return Err(self.invalid(&key, m.name.clone(), "'~' is reserved for scattered materials"));
            }
            m.resolve().map_err(|e| match e {
                crate::layout::LayoutError::Invalid { key, value, reason } => {
                    GeneratorError::Invalid { path: self.path.to_owned(), key, value, reason }
                }
                other => self.invalid(&format!("materials[{}]", m.name), String::new(), other.to_string()),
            })?;
        }
        let named = |key: &str, given: &Option<String>, default: &str| -> Result<String, GeneratorError> {
            let n = given.clone().unwrap_or_else(|| default.to_string());
            if names.contains(&n) {
                Ok(n)
            } else {
                let have = names.iter().cloned().collect::<Vec<_>>().join(", ");
                Err(self.invalid(key, n, format!("no such material (have: {have})")))
            }
        };
        let (blocks, restraints) = (&self.spec.blocks, &self.spec.restraints);
        let block = named("blocks.material", &blocks.material, &materials[0].name)?;
        let wedge = named("blocks.wedge_material", &blocks.wedge_material, &block)?;
        let table = named("restraints.table_material", &restraints.table_material, &block)?;
        Ok([block, wedge, table])
    }

    /// `[restraints.ends]`: free ends take no other key; rigid and spring ends a zone in
    /// (0, L/2); a spring a positive stiffness.
    fn ends(&self, length: f64) -> Result<Ends, GeneratorError> {
        let e = &self.spec.restraints.ends;
        let zone = |z: Option<f64>| -> Result<f64, GeneratorError> {
            match z {
                None => Err(self.invalid(
                    "restraints.ends.zone_m",
                    "missing".into(),
                    "rigid and spring ends need a zone in m",
                )),
                Some(z) if z.is_finite() && z > 0.0 && z < 0.5 * length => Ok(z),
                Some(z) => Err(self.invalid(
                    "restraints.ends.zone_m",
                    z.to_string(),
                    format!("must be in (0, L/2 = {})", 0.5 * length),
                )),
            }
        };
        match e.kind {
            EndKind::Free => {
                if e.zone_m.is_some() || e.stiffness_n_per_m.is_some() {
                    return Err(self.invalid(
                        "restraints.ends.kind",
                        "free".into(),
                        "free ends take no zone_m or stiffness_n_per_m",
                    ));
                }
                Ok(Ends::Free)
            }
            EndKind::Rigid => {
                if let Some(s) = e.stiffness_n_per_m {
                    return Err(self.invalid(
                        "restraints.ends.stiffness_n_per_m",
                        s.to_string(),
                        "a rigid restraint takes no stiffness",
                    ));
                }
                Ok(Ends::Rigid { zone: zone(e.zone_m)? })
            }
            EndKind::Spring => {
                let stiffness = match e.stiffness_n_per_m {
                    Some(s) => self.positive("restraints.ends.stiffness_n_per_m", s)?,
                    None => {
                        return Err(self.invalid(
                            "restraints.ends.stiffness_n_per_m",
                            "missing".into(),
                            "a spring needs a stiffness in N/m",
                        ))
                    }
                };
                Ok(Ends::Spring { zone: zone(e.zone_m)?, stiffness })
            }
        }
    }

    /// `[scatter]`: a Kn factor law with positive support; a friction offset law that keeps
    /// every material's friction angle in [0°, 90°); a bed seating gap law of unit `m`
    /// with its support in [0, 0.05] m (the closure laws' largest length,
    /// [`crate::closure::CLOSURE_RANGE_M`]).
    fn scatter(&self) -> Result<Option<Scatter>, GeneratorError> {
        let Some(s) = &self.spec.scatter else { return Ok(None) };
        let kn_factor = match &s.kn_factor {
            Some(r) => {
                let d = self.dist(r, "scatter.kn_factor", Unit::One)?;
                self.positive_support(&d, "scatter.kn_factor")?;
                Some(d)
            }
            None => None,
        };
        let friction_offset = match &s.friction_offset_deg {
            Some(r) => {
                let d = self.dist(r, "scatter.friction_offset_deg", Unit::Deg)?;
                let (lo, hi) = d.support();
                for m in &self.spec.materials {
                    if !(m.friction_deg + lo >= 0.0 && m.friction_deg + hi < 90.0) {
                        return Err(self.invalid(
                            "scatter.friction_offset_deg",
                            describe(r, &d),
                            format!(
                                "offsets in [{lo}, {hi}] take materials[{}].friction_deg = {} outside [0, 90)",
                                m.name, m.friction_deg
                            ),
                        ));
                    }
                }
                Some(d)
            }
            None => None,
        };
        let bed_seating_gap = match &s.bed_seating_gap_m {
            Some(r) => {
                let key = "scatter.bed_seating_gap_m";
                let d = self.dist(r, key, Unit::M)?;
                let (lo, hi) = d.support();
                let max = crate::closure::CLOSURE_RANGE_M.1;
                if !(lo >= 0.0 && hi <= max) {
                    let hint = if lo.is_finite() && hi.is_finite() {
                        ""
                    } else {
                        " (a normal or lognormal law is unbounded; use uniform or truncated_normal)"
                    };
                    return Err(self.invalid(
                        key,
                        describe(r, &d),
                        format!(
                            "gaps in [{lo}, {hi}] m: a bed's largest initial gap must lie in [0, {max}] m (no \
                             negative gap; the closure laws' largest length){hint}"
                        ),
                    ));
                }
                Some(d)
            }
            None => None,
        };
        Ok(Some(Scatter { kn_factor, friction_offset, bed_seating_gap }))
    }

    /// `[joints]`: every family's values in range, and no family the wall cannot have
    /// (`wedge` joints need the irregular arrangement).
    fn joints(&self, arrangement: &super::Arrangement) -> Result<(), GeneratorError> {
        let j = &self.spec.joints;
        j.resolve("joints").map_err(|e| match e {
            crate::layout::LayoutError::Invalid { key, value, reason } => self.invalid(&key, value, reason),
            other => self.invalid("joints", String::new(), other.to_string()),
        })?;
        if j.wedge.is_some() && !matches!(arrangement, super::Arrangement::Irregular(_)) {
            return Err(self.invalid(
                "joints.wedge",
                "given".into(),
                "only irregular walls have wedge stones: this wall has no wedge joint",
            ));
        }
        Ok(())
    }

    /// Joints no softer than a layout accepts ([`crate::layout::too_soft`] for every
    /// material's Kn and every joint family's: `kn_pa_per_m`, or `kn_factor` × the softest
    /// material's Kn, with the densest material), refused here as the wall file's value,
    /// naming the key and the resulting Kn, rather than by the check of the generated layout.
    fn softness(&self, gravity: f64) -> Result<(), GeneratorError> {
        use crate::layout::{too_soft, JointFamily};
        let materials = &self.spec.materials;
        let rho = materials.iter().map(|m| m.density_kg_per_m3).fold(0.0, f64::max);
        for m in materials {
            if let Some(reason) = too_soft(m.density_kg_per_m3, gravity, m.kn_pa_per_m) {
                let key = format!("materials[{}].kn_pa_per_m", m.name);
                return Err(self.invalid(&key, m.kn_pa_per_m.to_string(), reason));
            }
        }
        let kn_min = materials.iter().map(|m| m.kn_pa_per_m).fold(f64::INFINITY, f64::min);
        for fam in JointFamily::ALL {
            let Some(j) = self.spec.joints.get(fam) else { continue };
            let (kn, key, value) = match (j.kn_pa_per_m, j.kn_factor) {
                (Some(kn), _) => (kn, "kn_pa_per_m", kn),
                (None, Some(f)) => (kn_min * f, "kn_factor", f),
                (None, None) => continue,
            };
            if let Some(reason) = too_soft(rho, gravity, kn) {
                return Err(self.invalid(&format!("joints.{}.{key}", fam.name()), value.to_string(), reason));
            }
        }
        Ok(())
    }

    /// `[distributions.NAME]`: inline distributions are checked even when no key uses them.
    fn inline_distributions(&self) -> Result<(), GeneratorError> {
        for (n, d) in &self.spec.distributions {
            if !valid_name(n) {
                return Err(self.invalid(&format!("distributions.{n}"), n.clone(), "names are [A-Za-z0-9_-]+"));
            }
            d.resolve(n, self.path, &format!("distributions.{n}."))?;
        }
        Ok(())
    }
}
