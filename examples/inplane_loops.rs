//! The check of the cyclic loops (`drystone::study::inplane_loops`) of models given by hand,
//! on an in-plane study's measured curves: the baseline and each model run cyclic at each
//! stress with cyclic specimens, on the analysis's own layouts, their loops' damping ratio
//! against the specimens'. `drystone discrepancy` runs the same check on the baseline and
//! its tie; this runs it on any models, without the analysis.
//!
//! ```sh
//! cargo run --release --example inplane_loops -- studies/inplane_granite.toml \
//!     "rig_friction=0.035,joint_closure=0.14:4.7e-3" "jack_tilt=0.60,bed_stiffness=0.43"
//! ```
//!
//! Each model is a comma-separated list of effects `NAME=V` (`NAME=V1:V2` for two
//! parameters), as `drystone synthesize --effect` takes them. Prints the report's section.

use drystone::effects::Library;
use drystone::study::inplane_discrepancy::analysis_of;
use drystone::study::inplane_loops::{check_models, measured_loops, LoopCandidate};
use drystone::study::Study;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let Some(study) = args.next().map(PathBuf::from) else {
        return Err("usage: inplane_loops STUDY [MODEL ...], MODEL = NAME=V[,NAME=V...]".into());
    };
    let path = study;
    let study = Study::from_file(&path)?;
    let input = analysis_of(&study, study.discrepancy.clone())?;
    let Some((groups, test)) = measured_loops(&study, &input)? else {
        return Err(format!("{}: no cyclic specimen with a measured curve ([measured] curves)", path.display()).into());
    };
    let course_m = drystone::discrepancy::course_height(&input.setup);
    let lib = Library::builtin();
    let mut models: Vec<LoopCandidate> = vec![("baseline".into(), vec![], vec![])];
    for spec in args {
        let effects = spec
            .split(',')
            .map(|e| lib.parse(e.trim(), course_m))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| format!("{spec}: {e}"))?;
        let name = effects.iter().map(|e| e.def.name.clone()).collect::<Vec<_>>().join("+");
        models.push((name, vec![], effects));
    }
    let progress = |m: &str| eprintln!("{m}");
    let params = |sigma0_mpa: f64| drystone::loading::inplane::InPlaneParams { sigma0_mpa, ..test.clone() };
    let check = check_models(&input.setup, &params, &groups, &models, &progress)?;
    print!("{}", check.markdown());
    Ok(())
}
