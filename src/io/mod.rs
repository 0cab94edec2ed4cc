//! Files at the edges of the pipeline. Generated walls: VTK for ParaView ([`vtk`]) and SVG
//! drawings ([`svg`]).

pub mod plot;
pub mod svg;
pub mod table;
pub mod vtk;
