//! The `[section]` of a wall file: a single leaf, or a double-faced section whose leaves,
//! hearting and hearting pieces are each at least [`MIN_SECTION_PIECE_M`] thick.

use super::{Envelope, Resolver, MIN_SECTION_PIECE_M};
use crate::generator::wall::Section;
use crate::generator::GeneratorError;

fn thinner_than_a_piece() -> String {
    format!(
        "must be at least {MIN_SECTION_PIECE_M} m: a piece of a double-faced section thinner than twice the \
         solvers' contact margin (1 mm) is a sliver no solver resolves"
    )
}

impl Resolver<'_> {
    /// `[section]`: one leaf, or two leaves narrower together than the top width, each
    /// leaf, the hearting between them and a hearting piece at least
    /// [`MIN_SECTION_PIECE_M`].
    pub(super) fn section(&self, e: &Envelope) -> Result<Section, GeneratorError> {
        let Some(s) = &self.spec.section else { return Ok(Section::Single) };
        let double_only = [
            ("section.leaf_width_m", s.leaf_width_m.is_some()),
            ("section.hearting_stone_m", s.hearting_stone_m.is_some()),
            ("section.through_stone_spacing_m", s.through_stone_spacing_m.is_some()),
            ("section.through_stone_every_courses", s.through_stone_every_courses.is_some()),
        ];
        match s.leaves {
            1 => {
                if let Some((key, _)) = double_only.iter().find(|(_, given)| *given) {
                    return Err(self.invalid(
                        key,
                        "(given)".into(),
                        "applies to a double-faced section (leaves = 2) only",
                    ));
                }
                return Ok(Section::Single);
            }
            2 => {}
            n => return Err(self.invalid("section.leaves", n.to_string(), "must be 1 or 2")),
        }
        let leaf_width = match s.leaf_width_m {
            Some(w) => {
                let w = self.positive("section.leaf_width_m", w)?;
                if w < MIN_SECTION_PIECE_M {
                    return Err(self.invalid("section.leaf_width_m", w.to_string(), thinner_than_a_piece()));
                }
                if e.top_width - 2.0 * w < MIN_SECTION_PIECE_M && 2.0 * w < e.top_width {
                    return Err(self.invalid(
                        "section.leaf_width_m",
                        w.to_string(),
                        format!(
                            "leaves the hearting {} m wide at the top (top width {} m − 2 × {w} m), {}",
                            e.top_width - 2.0 * w,
                            e.top_width,
                            thinner_than_a_piece()
                        ),
                    ));
                }
                if 2.0 * w >= e.top_width {
                    return Err(self.invalid(
                        "section.leaf_width_m",
                        w.to_string(),
                        format!(
                            "two leaves must leave room for the hearting at the top: 2 × {w} m >= top width {} m",
                            e.top_width
                        ),
                    ));
                }
                Some(w)
            }
            None => None,
        };
        let hearting_stone = match s.hearting_stone_m {
            Some(_) if leaf_width.is_none() => {
                return Err(self.invalid(
                    "section.hearting_stone_m",
                    "(given)".into(),
                    "needs section.leaf_width_m (without it the leaves meet and there is no hearting)",
                ))
            }
            Some(v) => {
                let v = self.positive("section.hearting_stone_m", v)?;
                if v < MIN_SECTION_PIECE_M {
                    return Err(self.invalid("section.hearting_stone_m", v.to_string(), thinner_than_a_piece()));
                }
                Some(v)
            }
            None => None,
        };
        let through = match (s.through_stone_spacing_m, s.through_stone_every_courses) {
            (None, Some(_)) => {
                return Err(self.invalid(
                    "section.through_stone_every_courses",
                    "(given)".into(),
                    "needs section.through_stone_spacing_m",
                ))
            }
            (None, None) => None,
            (Some(sp), every) => {
                let sp = self.positive("section.through_stone_spacing_m", sp)?;
                let every = every.unwrap_or(1);
                if every == 0 {
                    return Err(self.invalid("section.through_stone_every_courses", "0".into(), "must be >= 1"));
                }
                Some((sp, every as usize))
            }
        };
        Ok(Section::Double { leaf_width, hearting_stone, through })
    }
}
