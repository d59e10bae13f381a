//! `MMOMENT` and `TSTEPVAR` on the rigid pendulum of decks/fmb/pendulum_rigid.dat: a moment at
//! the pivot that balances gravity holds the rod, error-controlled steps keep the TSTEP's
//! output times and meet their tolerance against a fine fixed-step run, and bad cards are
//! refused at their field. Andrews' mechanism under control: tests/fmb_andrews.rs.

mod common;

use std::io::Write;

use common::{root, run_deck};
use paraflex::deck::Deck;
use paraflex::model::Model;

fn pendulum() -> String {
    std::fs::read_to_string(root().join("decks/fmb/pendulum_rigid.dat")).expect("deck")
}

/// Runs `text`; returns time, XCM, YCM and the `/results/1/fmb` attribute `name` if any.
fn run(text: &str, attr: &str) -> (Vec<f64>, Vec<f64>, Vec<f64>, Option<i64>) {
    let (r, dir) = run_deck(text);
    r.unwrap_or_else(|e| panic!("{e}"));
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let g = file.group("results/1/fmb").unwrap();
    let read = |name: &str| -> Vec<f64> { g.dataset(name).unwrap().read_raw().unwrap() };
    let value = g.attr(attr).ok().map(|a| a.read_scalar::<i64>().unwrap());
    (
        read("time"),
        read("sensors/XCM"),
        read("sensors/YCM"),
        value,
    )
}

/// Gravity's moment about the pivot is r × m g = (0.5, 0, 0) × (0, −9.81, 0) = −4.905 N m
/// about z; an MMOMENT of +4.905 N m at the pivot marker cancels it, so the rod released
/// horizontal stays there (to the Newton tolerance), where without it it falls 0.5 m.
#[test]
fn a_moment_at_the_pivot_holds_the_rod_against_gravity() {
    let text = pendulum().replace(
        "ENDDATA",
        "MMOMENT,1,10,6,4.905,0.,0.,1.\nTABLED1,6\n,0.,1.,10.,1.,ENDT\nENDDATA",
    );
    let (_, _, y, _) = run(&text, "steps");
    let sag = y.iter().fold(0.0_f64, |a, y| a.max(y.abs()));
    assert!(sag < 1e-9, "the rod moved by {sag:e} m");
}

/// Generalized-α under `TSTEPVAR` with ATOL = 10⁻⁴ m writes the rows of the fixed-step run
/// (every 5 ms over 2.5 s) at the same times, and its centre of mass stays within twice the
/// tolerance of a fixed-step run at Δt = 0.1 ms (whose own error is ~10⁻⁶ m) over the whole
/// swing (1.6 times here: the pendulum's phase error accumulates over more than a period),
/// in fewer steps than the deck's 2500.
#[test]
fn controlled_steps_keep_the_output_times_and_meet_the_tolerance() {
    let galpha = pendulum().replace("GRAV,", "TINTEG,1,GALPHA\nGRAV,");
    let fine = galpha.replace("TSTEP,1,2500,1.e-3,5", "TSTEP,1,25000,1.e-4,50");
    let (t_ref, x_ref, y_ref, _) = run(&fine, "steps");
    let tol = 1e-4;
    let controlled = galpha.replace("GRAV,", &format!("TSTEPVAR,1,0.,{tol:.1e}\nGRAV,"));
    let (t, x, y, steps) = run(&controlled, "steps");
    assert_eq!(t.len(), t_ref.len());
    for (a, b) in t.iter().zip(&t_ref) {
        assert!((a - b).abs() < 1e-12, "output time {a} against {b}");
    }
    let error = x
        .iter()
        .zip(&x_ref)
        .chain(y.iter().zip(&y_ref))
        .fold(0.0_f64, |e, (a, b)| e.max((a - b).abs()));
    let steps = steps.expect("steps attribute");
    eprintln!("ATOL {tol:e} m: error {error:.3e} m in {steps} steps");
    assert!(error < 2.0 * tol, "error {error:.3e} m above 2 × {tol:e}");
    assert!(steps < 2500, "{steps} steps");
}

/// The errors of reading and building `text` (none: empty).
fn errors(text: &str) -> String {
    let mut file = tempfile::NamedTempFile::new().expect("temp file");
    file.write_all(text.as_bytes()).expect("write deck");
    let found = match Deck::read(file.path()) {
        Err(e) => vec![e.to_string()],
        Ok(deck) => Model::build(&deck).map_or_else(
            |e| e.iter().map(|x| x.to_string()).collect(),
            |_| Vec::new(),
        ),
    };
    found.join("\n")
}

/// Each bad card is an error at its card and field before any computation.
#[test]
fn bad_mmoment_and_tstepvar_cards_name_the_card_and_field() {
    let table = "TABLED1,6\n,0.,1.,10.,1.,ENDT\n";
    for (cards, expected) in [
        (
            format!("MARKER,12,0,,1.,0.,0.\nMMOMENT,1,12,6,1.,0.,0.,1.\n{table}"),
            ["MMOMENT 1", "field 3 (MK)", "on the ground"],
        ),
        (
            format!("MFORCE,1,11,6,1.,0.,1.,0.\nMMOMENT,1,10,6,1.,0.,0.,1.\n{table}"),
            ["MMOMENT 1", "duplicate", "MFORCE 1"],
        ),
        (
            "MMOMENT,1,10,7,1.,0.,0.,1.\n".to_string(),
            ["MMOMENT 1", "field 4 (TID)", "7"],
        ),
        (
            format!("MMOMENT,1,10,6,1.,0.,0.,0.\n{table}"),
            ["MMOMENT 1", "N1", "zero"],
        ),
        (
            "TSTEPVAR,1,0.\n".to_string(),
            ["TSTEPVAR 1", "RTOL", "both zero"],
        ),
        (
            "TSTEPVAR,1,1.e-4,,1.e-3,1.e-4\n".to_string(),
            ["TSTEPVAR 1", "HMAX", "below HMIN"],
        ),
        (
            "TSTEPVAR,2,1.e-4\n".to_string(),
            ["TSTEPVAR 2", "ID = 2 does not exist", "no TSTEP 2"],
        ),
    ] {
        let message = errors(&pendulum().replace("ENDDATA", &format!("{cards}ENDDATA")));
        assert!(!message.is_empty(), "accepted:\n{cards}");
        for part in expected {
            assert!(message.contains(part), "{part:?} not in: {message}");
        }
    }
}
