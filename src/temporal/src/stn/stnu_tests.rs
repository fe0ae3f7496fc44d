//! Hand cases of the dynamic-controllability check, each decided by both Morris 2014 ([`super::dc`]) and
//! the tightening fixpoint ([`super::dc_reference`]). Nodes: 0 = A (activation), 1 = C (contingent),
//! 2.. = controllable timepoints.

use super::dc_reference::is_dc;
use super::*;

fn link(n: usize, lower: Time, upper: Time) -> Stnu {
    let mut s = Stnu::new(n);
    s.add_contingent(0, 1, lower, upper).unwrap();
    s
}

fn both(s: &Stnu) -> Result<Dispatchable, NotDc> {
    let got = s.check_dc();
    assert_eq!(
        got.is_ok(),
        is_dc(s),
        "Morris 2014 and the reference disagree"
    );
    got
}

/// The squeeze of seed 1 §5: X must not be more than 2 before C, the move lasts [2, 5]. Executing X before
/// A + 3 would let the world end the move too late; the check derives the wait X ≥ A + 3 unless C.
#[test]
fn a_requirement_on_a_contingent_end_becomes_a_wait() {
    let mut s = link(3, 2, 5);
    s.add_requirement(2, 1, -INF, 2).unwrap(); // C − X ≤ 2
    s.add_requirement(0, 2, 0, INF).unwrap(); // X after A
    let d = both(&s).expect("DC: X waits for C or for A + 3");
    let waits: Vec<_> = d.waits_on(2).copied().collect();
    assert_eq!(
        waits,
        vec![Wait {
            node: 2,
            link: 0,
            delay: 3
        }]
    );
}

/// X must come 1 to 2 before C: only a prophet could (Morris, Muscettola & Vidal 2001's
/// "cannot be scheduled before the uncertainty is resolved").
#[test]
fn a_timepoint_tied_to_precede_a_contingent_end_is_not_dc() {
    let mut s = link(3, 1, 10);
    let r = s.add_requirement(2, 1, 1, 2).unwrap(); // C − X ∈ [1, 2]
    s.add_requirement(0, 2, 0, INF).unwrap();
    let e = both(&s).expect_err("not DC");
    assert_eq!(e.links, vec![0]);
    assert!(e.requirements.contains(&r), "{e}");
}

/// A reaction after the contingent end is always possible.
#[test]
fn reacting_after_a_contingent_end_is_dc() {
    let mut s = link(3, 1, 10);
    s.add_requirement(1, 2, 0, 1).unwrap(); // X − C ∈ [0, 1]
    let d = both(&s).expect("DC");
    // Its only wait (till A + 10 unless C) never binds: X follows C anyway.
    assert!(d.waits_on(2).all(|w| w.delay >= 10), "{:?}", d.waits);
}

/// A requirement that the duration be at least 5 when the world may choose 1 (the lower-case reduction).
#[test]
fn a_requirement_cutting_the_contingent_duration_is_not_dc() {
    let mut s = link(2, 1, 10);
    let r = s.add_requirement(0, 1, 5, INF).unwrap();
    let e = both(&s).expect_err("not DC");
    assert_eq!(
        (e.links.clone(), e.requirements.clone()),
        (vec![0], vec![r])
    );
    assert!(e.to_string().contains("contingent link"), "{e}");
}

/// Two moves in a row: [1, 3] then [1, 3] end within 6 of the first start, never within 5.
#[test]
fn chained_links_are_dc_only_with_room_for_both_maxima() {
    for (deadline, dc) in [(6, true), (5, false)] {
        let mut s = Stnu::new(3);
        s.add_contingent(0, 1, 1, 3).unwrap();
        s.add_contingent(1, 2, 1, 3).unwrap();
        s.add_requirement(0, 2, 0, deadline).unwrap();
        assert_eq!(both(&s).is_ok(), dc, "deadline {deadline}");
    }
}

/// Requirements alone inconsistent: not DC, and no link is blamed.
#[test]
fn an_inconsistent_stn_is_not_dc_and_names_only_requirements() {
    let mut s = Stnu::new(3);
    s.add_requirement(0, 1, 5, 10).unwrap();
    s.add_requirement(1, 2, 5, 10).unwrap();
    s.add_requirement(0, 2, 0, 8).unwrap();
    let e = both(&s).expect_err("inconsistent");
    assert!(e.links.is_empty());
    assert_eq!(e.requirements, vec![0, 1, 2]);
}

/// A wait through a second activation: starting the second move (node 2) at time t squeezes the first if
/// it must end within 4 of it: the second start waits till A + 6 unless C.
#[test]
fn an_activation_can_wait_for_another_link() {
    let mut s = Stnu::new(4);
    s.add_contingent(0, 1, 2, 10).unwrap();
    s.add_contingent(2, 3, 1, 2).unwrap();
    s.add_requirement(0, 2, 0, INF).unwrap();
    s.add_requirement(2, 1, -INF, 4).unwrap(); // C − start2 ≤ 4
    let d = both(&s).expect("DC");
    assert!(
        d.waits_on(2).any(|w| w.link == 0 && w.delay == 6),
        "{:?}",
        d.waits
    );
}

#[test]
fn bad_links_are_refused_with_their_reason() {
    let mut s = Stnu::new(3);
    assert_eq!(
        s.add_contingent(0, 1, 5, 2),
        Err(StnuError::BadBounds { lower: 5, upper: 2 })
    );
    assert_eq!(
        s.add_contingent(0, 1, 0, INF),
        Err(StnuError::BadBounds {
            lower: 0,
            upper: INF
        })
    );
    assert!(matches!(
        s.add_contingent(0, 7, 0, 1),
        Err(StnuError::NoSuchNode { node: 7, .. })
    ));
    s.add_contingent(0, 1, 0, 1).unwrap();
    assert_eq!(
        s.add_contingent(2, 1, 0, 1),
        Err(StnuError::TwiceContingent { node: 1 })
    );
}

/// Past a conflict, the waits of the rest of the network are still derived (what the executive honours
/// when the world may break the plan): the squeeze case of the first test, next to a link whose lower
/// bound a requirement cuts.
#[test]
fn best_effort_keeps_the_waits_beside_a_conflict() {
    let mut s = link(5, 2, 5);
    s.add_requirement(2, 1, -INF, 2).unwrap();
    s.add_requirement(0, 2, 0, INF).unwrap();
    s.add_contingent(3, 4, 1, 10).unwrap();
    s.add_requirement(3, 4, 5, INF).unwrap();
    let (d, conflict) = s.dispatch_best_effort();
    let conflict = conflict.expect("the second link is not DC");
    assert_eq!(conflict.links, vec![1]);
    assert!(
        d.waits_on(2).any(|w| w.link == 0 && w.delay == 3),
        "{:?}",
        d.waits
    );
    assert!(s.check_dc().is_err());
}
