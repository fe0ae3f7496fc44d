//! CI's share of `mavtempo fuzz`: a few thousand seeded mutations per target (domain, problem, config with
//! `[exec]`, scenario, goal files, the MAVLink goal intake) must neither panic nor give an error that does not
//! point inside the text. The long runs are `mavtempo fuzz --execs N` (README).

use mavtempo::fuzz::{self, Target};

#[test]
fn every_target_survives_a_short_seeded_run() {
    let save = tempfile::tempdir().expect("temp dir");
    for target in Target::ALL {
        let execs = if target == Target::Config {
            1_500
        } else {
            3_000
        };
        let r = fuzz::run(target, execs, 15, save.path());
        assert_eq!(r.execs, execs);
        assert!(
            r.failures == 0,
            "{}: {} failures, e.g. {:?} (inputs saved: replay with `mavtempo fuzz --target {} --replay FILE`)",
            target.name(),
            r.failures,
            r.kinds.first(),
            target.name()
        );
    }
}

#[test]
fn the_intake_seeds_reach_the_decider() {
    // Without this the intake harness could be feeding frames the intake never accepts.
    let seeds = fuzz::intake::corpus();
    assert_eq!(seeds.len(), 3);
    for s in &seeds {
        assert_eq!(fuzz::intake::decisions(s), 1, "a seed upload is decided");
    }
}

#[test]
fn generated_uploads_often_reach_the_decider() {
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
    let reached = (0..1_000)
        .filter(|_| fuzz::intake::decisions(&fuzz::intake::generate(&mut rng)) > 0)
        .count();
    // Edge values refuse many uploads on the way; enough must get through to exercise the decision.
    assert!((100..1_000).contains(&reached), "{reached} of 1000");
}

#[test]
fn a_bad_input_is_replayed_as_a_failure_only_if_it_fails() {
    // Non-UTF-8 text is an error located in the text, not a failure of the harness.
    assert_eq!(
        fuzz::replay(Target::Config, b"[link]\naddress = \"\xff\"\n"),
        Ok(())
    );
    assert_eq!(
        fuzz::replay(
            Target::Domain,
            b"domain d;\ntask t() (st, et) { (et - st) in [-oo, +oo]; }\n"
        ),
        Ok(())
    );
}
