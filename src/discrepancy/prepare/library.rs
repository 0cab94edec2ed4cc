//! The surrogate library: the baseline's full run, each effect's grid re-centred on it, the
//! pairs and triples of effects that share a reading, and the scatter hypothesis.

use super::*;

/// Builds the surrogate library: the baseline (every realization of `baseline`, the full
/// run), every effect's grid (the first `realizations` layouts of each group, common random
/// numbers) re-centred on the full baseline at the effect's neutral point
/// ([`Surface::Corrected`]), and the scatter hypothesis. The baseline and every candidate
/// are thereby scored with the same number of realizations: a candidate does not gain on
/// the baseline by being estimated from more layouts. Returns the library, the number of
/// forward runs its grids made and the grids' outcomes.
pub fn build_library(
    setup: &Setup,
    keys: &Keys,
    baseline: &[Vec<Outcome>],
    s: &Settings,
    defs: &[Arc<EffectDef>],
) -> Result<(Models, usize, GridRuns), DiscrepancyError> {
    build_library_from(setup, keys, baseline, s, defs, None)
}

/// [`build_library`], the grids of `earlier`'s groups read from its runs where they are
/// the same (`Earlier::grids`).
pub(super) fn build_library_from(
    setup: &Setup,
    keys: &Keys,
    baseline: &[Vec<Outcome>],
    s: &Settings,
    defs: &[Arc<EffectDef>],
    earlier: Option<&Earlier<'_>>,
) -> Result<(Models, usize, GridRuns), DiscrepancyError> {
    let course_m = course_height(setup);
    let plans: Vec<Plan> = defs.iter().map(|d| plan(d.clone(), s, course_m)).collect::<Result<_, _>>()?;
    let models: Vec<Vec<Effect>> =
        plans.iter().flat_map(|p| p.nodes.iter().filter_map(|(_, e)| e.clone().map(|e| vec![e]))).collect();
    let grid_setup = with_realizations(setup, s.realizations);
    let base_grid: Vec<Vec<Outcome>> = baseline
        .iter()
        .zip(&grid_setup.groups)
        .map(|(o, g)| o[..(g.realizations as usize).min(o.len())].to_vec())
        .collect();
    let (outcomes, runs) = match earlier.and_then(|e| e.grids(&plans, &grid_setup)) {
        Some(known) => run_models_knowing(&grid_setup, &models, &base_grid, &known),
        None => (run_models(&grid_setup, &models, Some(&base_grid)), forward_runs(&grid_setup, &models, true)),
    };
    let base_sims = keys.simulated(&base_grid);
    let full_sims = keys.simulated(baseline);
    let mut next = outcomes.into_iter();
    // Every plan's nodes with their outcomes (the neutral node's the baseline's).
    let nodes: Vec<Vec<Node>> = plans
        .iter()
        .map(|p| {
            p.nodes
                .iter()
                .map(|(x, e)| {
                    let outs = match e {
                        Some(_) => next.next().unwrap_or_default(),
                        None => base_grid.clone(),
                    };
                    (x.clone(), e.clone(), outs)
                })
                .collect()
        })
        .collect();
    let mut candidates = Vec::new();
    for (p, nodes) in plans.iter().zip(&nodes) {
        let sims: Vec<(Vec<f64>, Vec<Simulated>)> = nodes
            .iter()
            .map(|(x, e, outs)| (x.clone(), if e.is_some() { keys.simulated(outs) } else { base_sims.clone() }))
            .collect();
        let surface = p.surface(sims);
        let surface = Surface::Corrected { inner: Box::new(surface), x0: p.neutral(), full: full_sims.clone() };
        candidates.push(Candidate {
            effects: vec![p.def.clone()],
            params: p.params.clone(),
            surface,
            kinds: kinds(setup),
        });
    }
    let (readings_pairs, readings_triples) = if rereads(setup) {
        (
            readings_pairs(&grid_setup, keys, &plans, &nodes, &full_sims),
            readings_triples(&grid_setup, keys, &plans, &nodes, &full_sims),
        )
    } else {
        (vec![], vec![])
    };
    if s.scatter {
        let angle = keys.keys.iter().map(|(_, o)| o.is_angle()).collect();
        let mechanism = keys.keys.iter().map(|(_, o)| o.is_mechanism()).collect();
        candidates.push(Candidate::scatter(full_sims.clone(), angle, mechanism));
    }
    let grids: GridRuns = plans
        .iter()
        .zip(nodes)
        .map(|(p, nodes)| {
            let nodes = nodes.into_iter().map(|(x, e, outs)| (x, e.map(|e| (e, outs)))).collect();
            (p.def.name.clone(), nodes)
        })
        .collect();
    Ok((Models { baseline: full_sims, candidates, readings_pairs, readings_triples }, runs, grids))
}

/// A grid node with its outcomes: search coordinates, the effect there (`None`: the
/// neutral node, the baseline's run) and the outcomes, `[group][realization]`.
type Node = (Vec<f64>, Option<Effect>, Vec<Vec<Outcome>>);

/// The pairs of every one-parameter effect that acts on the readings only (`r`) with every
/// other plan of one or two parameters (`p`; another effect on the readings only once, the
/// later with the earlier): a tensor grid over `r`'s coordinate then `p`'s, every node
/// `p`'s outcomes at its node read again with `r`'s effect at its node (none at `r`'s
/// neutral node), re-centred on the baseline's full run at both neutral points as the
/// single effects are. No run: the outcomes are those of `p`'s grid.
fn readings_pairs(
    grid_setup: &Setup,
    keys: &Keys,
    plans: &[Plan],
    nodes: &[Vec<Node>],
    full_sims: &[Simulated],
) -> Vec<Candidate> {
    let mut out = Vec::new();
    for (ri, r) in plans.iter().enumerate() {
        if !r.def.acts_on_readings_only() || r.params.len() != 1 {
            continue;
        }
        for (pi, p) in plans.iter().enumerate() {
            if pi == ri || (p.def.acts_on_readings_only() && pi < ri) || p.params.len() > 2 {
                continue;
            }
            let mut sims = Vec::new();
            for (_, er, _) in &nodes[ri] {
                for (_, _, outs) in &nodes[pi] {
                    let o = match er {
                        Some(e) => reread_outcomes(grid_setup, outs, std::slice::from_ref(e)),
                        None => outs.clone(),
                    };
                    sims.push(keys.simulated(&o));
                }
            }
            let xr: Vec<f64> = nodes[ri].iter().map(|(x, _, _)| x[0]).collect();
            let mut xp1: Vec<f64> = nodes[pi].iter().map(|(x, _, _)| x[0]).collect();
            xp1.dedup();
            let inner = if p.params.len() == 1 {
                Surface::Grid { x1: xr, x2: xp1, sims }
            } else {
                let mut xp2: Vec<f64> = nodes[pi].iter().map(|(x, _, _)| x[1]).collect();
                xp2.sort_by(f64::total_cmp);
                xp2.dedup();
                Surface::Grid3 { x1: xr, x2: xp1, x3: xp2, sims }
            };
            let x0: Vec<f64> = r.neutral().into_iter().chain(p.neutral()).collect();
            out.push(Candidate {
                effects: vec![r.def.clone(), p.def.clone()],
                params: r.params.iter().chain(&p.params).cloned().collect(),
                surface: Surface::Corrected { inner: Box::new(inner), x0, full: full_sims.to_vec() },
                kinds: kinds(grid_setup),
            });
        }
    }
    out
}

/// The triples of two one-parameter effects that act on the readings only (`r`, `q`, in
/// the library's order) with every one-parameter plan that moves the wall (`p`): a tensor
/// grid over `r`'s coordinate, `q`'s, then `p`'s, every node `p`'s outcomes at its node
/// read again with `r`'s and `q`'s effects at theirs, re-centred on the baseline's full run
/// at the three neutral points. No run. They are not ranked (the analysis tries pairs);
/// a check that reads one of the rig's forces elsewhere refits them with that force held
/// (`Run::refit_held`, the in-plane loops' bearing friction).
fn readings_triples(
    grid_setup: &Setup,
    keys: &Keys,
    plans: &[Plan],
    nodes: &[Vec<Node>],
    full_sims: &[Simulated],
) -> Vec<Candidate> {
    let reads: Vec<usize> =
        (0..plans.len()).filter(|&i| plans[i].def.acts_on_readings_only() && plans[i].params.len() == 1).collect();
    let mut out = Vec::new();
    for (a, &ri) in reads.iter().enumerate() {
        for &qi in &reads[a + 1..] {
            for (pi, p) in plans.iter().enumerate() {
                if p.def.acts_on_readings_only() || p.params.len() != 1 {
                    continue;
                }
                let mut sims = Vec::new();
                for (_, er, _) in &nodes[ri] {
                    for (_, eq, _) in &nodes[qi] {
                        let both: Vec<Effect> = er.iter().chain(eq.iter()).cloned().collect();
                        for (_, _, outs) in &nodes[pi] {
                            let o =
                                if both.is_empty() { outs.clone() } else { reread_outcomes(grid_setup, outs, &both) };
                            sims.push(keys.simulated(&o));
                        }
                    }
                }
                let xs = |i: usize| -> Vec<f64> { nodes[i].iter().map(|(x, _, _)| x[0]).collect() };
                let (r, q) = (&plans[ri], &plans[qi]);
                let x0: Vec<f64> = r.neutral().into_iter().chain(q.neutral()).chain(p.neutral()).collect();
                out.push(Candidate {
                    effects: vec![r.def.clone(), q.def.clone(), p.def.clone()],
                    params: r.params.iter().chain(&q.params).chain(&p.params).cloned().collect(),
                    surface: Surface::Corrected {
                        inner: Box::new(Surface::Grid3 { x1: xs(ri), x2: xs(qi), x3: xs(pi), sims }),
                        x0,
                        full: full_sims.to_vec(),
                    },
                    kinds: kinds(grid_setup),
                });
            }
        }
    }
    out
}
