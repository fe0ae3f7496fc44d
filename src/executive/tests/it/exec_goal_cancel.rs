//! Goals withdrawn by their ground station (issue 30 item 3): a goal held in the plan leaves it with the
//! actions that served only it (fate `cancelled`), a goal still being inserted leaves the queue, the
//! station is told through the upload's watch, and the goals the plan held before are untouched.

use crate::support::picture_goal;
use crate::support::rover_mock;

use mavtempo_executive::exec::cancel::pursues;
use mavtempo_executive::exec::executive::{Executive, Fate};
use mavtempo_vehicle::goals::{GoalBatch, GoalCancel};
use mavtempo_vehicle::{GoalVerdict, VehicleEvent};
use picture_goal::picture;
use rover_mock::executive;

fn actions(ex: &Executive) -> Vec<String> {
    ex.plan()
        .live_actions()
        .map(|a| ex.action_text(a))
        .collect()
}

fn insert(ex: &mut Executive) {
    for _ in 0..50 {
        ex.repair_phase(0, &|| 0);
        ex.answer_goal_batches();
        if ex.insertion_queue().is_empty() {
            return;
        }
    }
    panic!("insertion still in progress");
}

#[test]
fn a_cancelled_goal_leaves_the_plan_with_the_actions_that_served_only_it() {
    let mut ex = executive();
    let before = actions(&ex);
    let (batch, mut rx, mut later) = GoalBatch::with_later(vec![picture("g6", 12.0, -8.0, 1)]);
    ex.integrate(VehicleEvent::Goals(batch), 0);
    insert(&mut ex);
    assert_eq!(
        rx.try_recv().expect("answered"),
        vec![GoalVerdict::Accepted]
    );
    assert!(pursues(ex.plan(), "g6"));
    let with = actions(&ex);
    assert!(with.iter().any(|a| a.contains("g6_loc")), "{with:?}");

    let (cancel, mut reply) =
        GoalCancel::new(vec!["g6".into()], "cleared by the ground station".into());
    ex.integrate(VehicleEvent::Cancel(cancel), 0);
    assert_eq!(reply.try_recv().expect("confirmed"), vec!["g6".to_string()]);
    assert!(!pursues(ex.plan(), "g6"));
    let f = ex
        .goal_fates()
        .into_iter()
        .find(|f| f.name == "g6")
        .expect("g6");
    assert_eq!(f.fate, Fate::Cancelled);
    assert_eq!(f.reason_text(), "cleared by the ground station");
    assert_eq!(
        later.try_recv().expect("told"),
        (
            0,
            GoalVerdict::Cancelled("cleared by the ground station".into())
        )
    );
    // The picture at g6_loc is gone; the plan is repaired without it and still holds g1 and g2.
    for _ in 0..50 {
        ex.repair_phase(0, &|| 0);
    }
    let after = actions(&ex);
    assert!(
        !after.iter().any(|a| a.starts_with("take_picture(g6_loc")),
        "{after:?}"
    );
    let mut plan = ex.plan().clone();
    assert!(plan.flaws().is_empty(), "repaired: {:?}", plan.flaws());
    assert_eq!(ex.pending_goals().len(), 2, "{:?}", ex.goal_fates());
    assert!(
        after.len() < with.len() && before.len() <= after.len(),
        "{before:?} {with:?} {after:?}"
    );
    // Cancelling again: nothing held by that name.
    let (cancel, mut reply) = GoalCancel::new(vec!["g6".into()], "again".into());
    ex.integrate(VehicleEvent::Cancel(cancel), 0);
    assert!(reply.try_recv().expect("answered").is_empty());
}

#[test]
fn a_goal_being_inserted_is_cancelled_out_of_the_queue() {
    let mut ex = executive();
    let (batch, _rx, _later) = GoalBatch::with_later(vec![picture("g6", 12.0, -8.0, 1)]);
    ex.integrate(VehicleEvent::Goals(batch), 0);
    assert_eq!(ex.insertion_queue(), ["g6"]);
    let (cancel, mut reply) = GoalCancel::new(vec!["g6".into()], "left out".into());
    ex.integrate(VehicleEvent::Cancel(cancel), 0);
    assert_eq!(reply.try_recv().expect("confirmed"), vec!["g6".to_string()]);
    assert!(ex.insertion_queue().is_empty());
    assert!(ex
        .goal_fates()
        .iter()
        .any(|f| f.name == "g6" && f.fate == Fate::Cancelled));
}
