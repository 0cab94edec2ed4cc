//! Legacy VTK (ASCII `POLYDATA`) of a layout, for ParaView.
//!
//! One polygon cell per block face, points in the table frame (m). Cell data: `block` (the
//! block's index in the layout) and any integer fields the caller adds per block (the
//! generator adds `course`, `wedge` and `restrained`), repeated on every face of the block.

use crate::layout::Layout;
use std::fmt::Write as _;

/// The VTK text of `layout`. Each field is `(name, one value per block)`; fields whose
/// length is not the number of blocks are skipped.
pub fn layout_to_vtk(layout: &Layout, fields: &[(&str, Vec<i64>)]) -> String {
    let mut points = String::new();
    let mut polys = String::new();
    let mut cell_block = Vec::new();
    let mut npts = 0usize;
    let mut ncells = 0usize;
    let mut size = 0usize;
    for (bi, b) in layout.blocks.iter().enumerate() {
        let base = npts;
        for v in &b.shape.vertices {
            let _ = writeln!(points, "{:.17e} {:.17e} {:.17e}", v.x, v.y, v.z);
        }
        npts += b.shape.vertices.len();
        for f in &b.shape.faces {
            let _ = write!(polys, "{}", f.vertices.len());
            for &i in &f.vertices {
                let _ = write!(polys, " {}", base + i);
            }
            polys.push('\n');
            ncells += 1;
            size += 1 + f.vertices.len();
            cell_block.push(bi);
        }
    }
    let mut out = String::new();
    out.push_str("# vtk DataFile Version 3.0\n");
    // The header line: at most 256 characters, ASCII.
    let title: String =
        layout.name.chars().map(|c| if c.is_ascii() && !c.is_ascii_control() { c } else { '?' }).take(250).collect();
    let _ = writeln!(out, "{title}");
    out.push_str("ASCII\nDATASET POLYDATA\n");
    let _ = writeln!(out, "POINTS {npts} double");
    out.push_str(&points);
    let _ = writeln!(out, "POLYGONS {ncells} {size}");
    out.push_str(&polys);
    let _ = writeln!(out, "CELL_DATA {ncells}");
    let _ = writeln!(out, "SCALARS block int 1\nLOOKUP_TABLE default");
    for &b in &cell_block {
        let _ = writeln!(out, "{b}");
    }
    for (name, vals) in fields {
        if vals.len() != layout.blocks.len() {
            continue;
        }
        let name: String = name.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
        let _ = writeln!(out, "SCALARS {name} int 1\nLOOKUP_TABLE default");
        for &b in &cell_block {
            let _ = writeln!(out, "{}", vals[b]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_has_8_points_and_6_quads() {
        let l = crate::layout::LayoutSpec::from_json(
            r#"{"version":1,"name":"box","materials":[{"name":"m","density_kg_per_m3":2000,"kn_pa_per_m":1e8,
            "ks_pa_per_m":5e7,"friction_deg":30}],"table":{"material":"m"},"blocks":[{"id":"b0","material":"m",
            "vertices":[[0,-0.05,0],[0.3,-0.05,0],[0.3,0.05,0],[0,0.05,0],[0,-0.05,0.2],[0.3,-0.05,0.2],[0.3,0.05,0.2],[0,0.05,0.2]]}]}"#,
        )
        .and_then(|s| s.resolve())
        .expect("a valid box");
        let s = layout_to_vtk(&l, &[("course", vec![0])]);
        assert!(s.contains("POINTS 8 double"));
        assert!(s.contains("POLYGONS 6 30"));
        assert!(s.contains("CELL_DATA 6"));
        assert!(s.contains("SCALARS course int 1"));
    }
}
