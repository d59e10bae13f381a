//! `SOL OPTIMIZE`: a multi-objective design study on the deck's mechanism (DESIGN.md §12,
//! thesis ch. 5–6), one study per subcase.
//!
//! The subcase is prepared as a `SOL FMB` run ([`PreparedFmb`]: mechanism, systems, outputs,
//! time grid, `PVAL` for the parameters no variable sets), the study read from the design
//! cards and checked against the mechanism before any evaluation ([`Study`]). One evaluation
//! is the transient at the design's parameters with nothing written, its MSENSOR histories
//! reduced to the responses ([`Study::evaluate`]); the search (`MOOPT NSGA2` or the
//! full-factorial `GRID`) evaluates batches on NPAR threads ([`Threaded`]), a failed
//! evaluation recorded and the study going on. Each evaluation is journaled as it completes
//! ([`super::optimize_journal`]); with `MOOPT` START = RESUME the designs the journal holds
//! are taken from it instead of evaluated. The report ([`crate::optimize::summarize`]) and
//! the histories of the representative designs (the front's extremes and knee, run again) are
//! written by [`super::optimize_output`].

use std::time::Instant;

use super::fmb::PreparedFmb;
use super::optimize_engine::Engine;
use super::optimize_gradient::Gradient;
use super::optimize_journal::{Header, Journal, journal_path};
use super::optimize_output::{OptimizeSummary, Representative, write_study};
use super::optimize_study::Study;
use super::{Basis, Clock, Driver, RunContext, RunError, SubcaseSummary};
use crate::deck::Solution;
use crate::deck::cards::SearchMethod;
use crate::deck::case_control::Subcase;
use crate::multibody::{Scheme, Start};
use crate::optimize::gradient::{GradientSearch, WithGradient};
use crate::optimize::grid::full_factorial;
use crate::optimize::{Archive, Design, EvalError, Evaluated, Nsga2, Threaded, summarize};

/// The `SOL OPTIMIZE` driver, on the deck's mechanism.
pub struct Optimize;

impl Driver for Optimize {
    fn name(&self) -> &'static str {
        "OPTIMIZE"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::Optimize]
    }

    fn basis(&self) -> Basis {
        Basis::Mesh
    }

    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        ctx.model
            .subcases
            .iter()
            .map(|sub| clock.time(format!("subcase {}: optimize", sub.id), || study(ctx, sub)))
            .collect()
    }
}

/// Subcase `sub` prepared as a `SOL FMB` run and its study checked against it.
fn prepare(ctx: &RunContext, sub: &Subcase) -> Result<(PreparedFmb, Study), RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    if ctx.model.mechanism.is_empty() && sub.fmb.is_none() {
        return Err(case(
            "SOL OPTIMIZE runs on a mechanism: FLEXB or RIGIDB bodies, MARKERs and JOINTs (or FMB = 'file.h5', the /pfmb of a SOL FMB run)".into(),
        ));
    }
    let prepared = PreparedFmb::new(ctx, sub)?;
    if prepared.grid.intervals.is_empty() {
        return Err(case(
            "SOL OPTIMIZE evaluates a transient: give TSTEP = <sid> in case control".into(),
        ));
    }
    let study = Study::of_deck(&ctx.deck.bulk, &prepared).map_err(|e| case(e.join("\n")))?;
    if study.search.method == SearchMethod::Grad {
        let m = &study.search;
        let refuse = |why: &str| {
            case(format!(
                "{}: MOOPT {}: field 3 (METHOD): GRAD {why}",
                m.loc, m.id
            ))
        };
        if prepared.start != Start::Assembled {
            return Err(refuse(
                "needs FMBSTART = ASSEMBLE (the static equilibrium's sensitivities are not computed)",
            ));
        }
        if prepared.grid.control.is_some() {
            return Err(refuse(
                "needs fixed steps (TSTEPVAR's accepted steps depend on the parameters)",
            ));
        }
        if let Scheme::GeneralizedAlpha { .. } = prepared.scheme {
            return Err(refuse(
                "needs TINTEG BDF1 or BDF2 (generalized-α starts from accelerations that depend on the parameters)",
            ));
        }
    }
    Ok((prepared, study))
}

/// Evaluates `designs` with the study of subcase `subcase` as `SOL OPTIMIZE` evaluates a batch
/// (NPAR threads), nothing written: the design evaluation as a pure function, for an engine
/// outside this process (`paraflex evaluate`). A design of the wrong length or outside the
/// variables' domains is an error naming it.
pub fn evaluate_designs(
    ctx: &RunContext,
    subcase: u32,
    designs: &[Design],
) -> Result<Vec<Evaluated>, RunError> {
    let (prepared, study) = prepare_for(ctx, subcase, designs)?;
    let threaded = Threaded::new(study.search.npar, |design: &[f64]| {
        study.evaluate(&prepared, design)
    })
    .map_err(|e| RunError::Case {
        subcase,
        what: e.to_string(),
    })?;
    Ok(threaded.batch(designs))
}

/// The responses of `designs` and their gradients with respect to the continuous variables
/// ([`Study::gradient`]), one design after the other (`paraflex evaluate --gradient`); a
/// design whose run or gradient fails gives its message.
pub fn gradients_of_designs(
    ctx: &RunContext,
    subcase: u32,
    designs: &[Design],
) -> Result<Vec<Result<Gradient, String>>, RunError> {
    let (prepared, study) = prepare_for(ctx, subcase, designs)?;
    Ok(designs
        .iter()
        .map(|d| study.gradient(&prepared, d))
        .collect())
}

/// Subcase `subcase` prepared and its study checked, and `designs` checked to be points of
/// its space.
fn prepare_for(
    ctx: &RunContext,
    subcase: u32,
    designs: &[Design],
) -> Result<(PreparedFmb, Study), RunError> {
    let sub = (ctx.model.subcases.iter())
        .find(|s| s.id == subcase)
        .ok_or_else(|| RunError::Case {
            subcase,
            what: format!("the deck has no subcase {subcase}"),
        })?;
    let (prepared, study) = prepare(ctx, sub)?;
    for (i, d) in designs.iter().enumerate() {
        let inside = d.len() == study.space.len()
            && (d.iter().zip(&study.space.variables)).all(|(x, v)| v.contains(*x));
        if !inside {
            return Err(RunError::Case {
                subcase,
                what: format!(
                    "design {i} {d:?} is not a point of the study's space ({} variable(s): {})",
                    study.space.len(),
                    (study.space.variables.iter())
                        .map(|v| v.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
    }
    Ok((prepared, study))
}

/// Where a study's batches are evaluated.
enum Evaluator<F> {
    /// NPAR threads of this process.
    Threads(Threaded<F>),
    /// An engine outside this process (`paraflex run --engine`).
    Engine(Engine),
}

/// `n` evaluations failed because the engine did.
fn engine_failed(why: &str, n: usize) -> Vec<Evaluated> {
    let failed = Evaluated {
        result: Err(EvalError(format!("not evaluated: {why}"))),
        seconds: 0.0,
    };
    vec![failed; n]
}

/// Runs the study of subcase `sub` and writes it.
fn study(ctx: &RunContext, sub: &Subcase) -> Result<SubcaseSummary, RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    let (prepared, study) = prepare(ctx, sub)?;
    let header = Header {
        variables: study
            .space
            .variables
            .iter()
            .map(|v| v.name.clone())
            .collect(),
        responses: study.responses.iter().map(|r| r.name.clone()).collect(),
    };
    let path = journal_path(ctx.output.path(), sub.id);
    let journal = Journal::open(&path, &header, study.search.resume).map_err(case)?;
    let journal_shown = path.display().to_string();
    let threads = study.search.npar;
    // each evaluation journaled as it completes (a panic is caught outside, not journaled)
    let journal_error = std::sync::Mutex::new(None);
    let keep_error = |e: String| {
        (journal_error.lock().unwrap_or_else(|p| p.into_inner())).get_or_insert(e);
    };
    if study.search.method == SearchMethod::Grad && ctx.engine.is_some() {
        return Err(case(
            "MOOPT GRAD evaluates its designs in this process, one after the other (each step needs the last gradient): run it without --engine".into(),
        ));
    }
    let mut evaluator = match ctx.engine {
        None => Evaluator::Threads(
            Threaded::new(threads, |design: &[f64]| {
                let start = Instant::now();
                let result = study.evaluate(&prepared, design);
                let evaluated = Evaluated {
                    result,
                    seconds: start.elapsed().as_secs_f64(),
                };
                if let Err(e) = journal.record(design, &evaluated) {
                    keep_error(e);
                }
                evaluated.result
            })
            .map_err(|e| case(e.to_string()))?,
        ),
        Some(command) => {
            Evaluator::Engine(Engine::start(command, &ctx.deck.path, sub.id).map_err(case)?)
        }
    };
    let engine_shown = match &evaluator {
        Evaluator::Threads(_) if threads == 0 => "one thread per core".to_string(),
        Evaluator::Threads(_) => format!("{threads} thread(s)"),
        Evaluator::Engine(e) => format!("the engine `{}`", e.command()),
    };
    let total = study.budget();
    let mut done = 0;
    let mut resumed = 0;
    // an engine failure ends the study; the search gets failed evaluations meanwhile
    let mut engine_error: Option<String> = None;
    let mut batch = |designs: &[Design]| -> Vec<Evaluated> {
        // the designs the journal holds are not evaluated again
        let known: Vec<Option<Evaluated>> = designs.iter().map(|d| journal.known(d)).collect();
        let missing: Vec<Design> = (designs.iter().zip(&known))
            .filter(|(_, k)| k.is_none())
            .map(|(d, _)| d.clone())
            .collect();
        resumed += designs.len() - missing.len();
        let fresh = match &mut evaluator {
            Evaluator::Threads(threaded) => threaded.batch(&missing),
            Evaluator::Engine(engine) if engine_error.is_none() => engine
                .batch(&missing, |design, evaluated| {
                    if let Err(e) = journal.record(design, evaluated) {
                        keep_error(e);
                    }
                })
                .unwrap_or_else(|e| {
                    let failed = engine_failed(&e, missing.len());
                    engine_error = Some(e);
                    failed
                }),
            Evaluator::Engine(_) => engine_failed("the engine failed before", missing.len()),
        };
        let mut fresh = fresh.into_iter();
        let results = known
            .into_iter()
            .map(|k| k.unwrap_or_else(|| fresh.next().expect("one result per missing design")))
            .collect();
        done += designs.len();
        ctx.progress.step("optimize: evaluations", done, total);
        results
    };
    let start = Instant::now();
    let archive = match study.search.method {
        SearchMethod::Grad => {
            // one design after the other: each step of the descent needs the last gradient
            let mut evaluate = |design: &[f64]| -> WithGradient {
                let start = Instant::now();
                let (result, gradient) = match study.gradient(&prepared, design) {
                    Ok(g) => (Ok(g.responses), Some(g.gradient)),
                    Err(e) => (Err(EvalError(e)), None),
                };
                let evaluated = Evaluated {
                    result,
                    seconds: start.elapsed().as_secs_f64(),
                };
                if let Err(e) = journal.record(design, &evaluated) {
                    keep_error(e);
                }
                done += 1;
                ctx.progress.step("optimize: evaluations", done, total);
                (evaluated, gradient)
            };
            let m = &study.search;
            GradientSearch {
                weights: m.pop as usize,
                budget: m.neval as usize,
            }
            .run(&study.space, &study.scoring, &study.start, &mut evaluate)
        }
        SearchMethod::Grid => {
            let mut archive = Archive::default();
            let levels = study.search.pop as usize;
            archive.evaluate(full_factorial(&study.space, levels), &mut batch);
            archive
        }
        SearchMethod::Nsga2 => {
            let m = &study.search;
            Nsga2::new(m.pop as usize, m.neval as usize, m.seed).run(
                &study.space,
                &study.scoring,
                &mut batch,
            )
        }
    };
    let wall = start.elapsed().as_secs_f64();
    if let Some(e) = engine_error {
        return Err(case(format!(
            "{e}; the evaluations done are in the journal {journal_shown} (MOOPT START = RESUME goes on from them)"
        )));
    }
    if let Evaluator::Engine(engine) = evaluator {
        engine.finish().map_err(case)?;
    }
    if let Some(e) = journal_error
        .into_inner()
        .unwrap_or_else(|p| p.into_inner())
    {
        return Err(case(e));
    }
    let summary = summarize(&archive, &study.scoring, None);
    // the representative designs run again for their histories (an evaluation keeps only
    // its responses)
    let representatives = Representative::of(&summary, &study)
        .into_iter()
        .map(|r| {
            let design = &archive.designs[r.design];
            let histories = study
                .histories(&prepared, design)
                .map_err(|e| case(format!("representative design {}: {e}", r.design)))?;
            Ok((r, histories))
        })
        .collect::<Result<Vec<_>, RunError>>()?;
    let sensors: Vec<String> = prepared.sensors.iter().map(|s| s.name.clone()).collect();
    write_study(
        ctx,
        sub.id,
        &study,
        &archive,
        &summary,
        &representatives,
        &sensors,
    )?;
    Ok(SubcaseSummary {
        id: sub.id,
        autospc: Vec::new(),
        result: Box::new(OptimizeSummary::new(
            &study,
            &archive,
            &summary,
            wall,
            engine_shown,
            (journal_shown, resumed),
        )),
    })
}
