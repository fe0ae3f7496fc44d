//! Ground tasks for the forward search's tests: one-happening actions, a rover on a line of waypoints
//! that spends energy to move and recharges to full in the sun, and a tank drained below a level.

use super::{Cond, GroundAction, GroundTask, Happening, NumCond, NumEffect, NumExpr};
use crate::pddl::ast::{Cmp, NumOp};

/// Energy, the rover's only numeric variable.
pub const ENERGY: u32 = 0;
/// What a move costs.
pub const MOVE_COST: f64 = 8.0;
/// The level a recharge fills to.
pub const FULL: f64 = 80.0;

fn ge(var: u32, v: f64) -> NumCond {
    NumCond {
        cmp: Cmp::Ge,
        lhs: NumExpr::Var(var),
        rhs: NumExpr::Const(v),
    }
}

/// An action of one happening: its start needs `pos` and `num`, adds `add` and deletes `del`.
pub fn action(
    name: &str,
    pos: Vec<u32>,
    num: Vec<NumCond>,
    add: Vec<u32>,
    del: Vec<u32>,
) -> GroundAction {
    GroundAction {
        name: name.into(),
        args: Vec::new(),
        start: Happening {
            pre: Cond {
                pos,
                neg: Vec::new(),
                num,
            },
            add,
            del,
            num: Vec::new(),
        },
        over_all: Cond::default(),
        end: Happening::default(),
        duration: None,
    }
}

/// Waypoints `0..n` on a line, atom `at(i) = i`; the sun at waypoint `sun`; the rover at 0 with
/// `energy`; goal: at the last waypoint. `move-i-j` (neighbours) needs and spends [`MOVE_COST`];
/// `recharge-i` (in the sun) fills to [`FULL`].
pub fn line(n: u32, sun: u32, energy: f64) -> GroundTask {
    let mut actions = Vec::new();
    for i in 0..n {
        for j in [i.wrapping_sub(1), i + 1] {
            if j >= n {
                continue;
            }
            let mut a = action(
                &format!("move-{i}-{j}"),
                vec![i],
                vec![ge(ENERGY, MOVE_COST)],
                vec![j],
                vec![i],
            );
            a.start.num.push(NumEffect {
                op: NumOp::Decrease,
                var: ENERGY,
                expr: NumExpr::Const(MOVE_COST),
            });
            actions.push(a);
        }
    }
    let mut recharge = action(
        &format!("recharge-{sun}"),
        vec![sun],
        Vec::new(),
        Vec::new(),
        Vec::new(),
    );
    recharge.start.num.push(NumEffect {
        op: NumOp::Assign,
        var: ENERGY,
        expr: NumExpr::Const(FULL),
    });
    actions.push(recharge);
    GroundTask {
        atoms: (0..n).map(|i| format!("(at w{i})")).collect(),
        init: vec![0],
        nums: vec!["(energy)".into()],
        init_nums: vec![energy],
        goal: Cond {
            pos: vec![n - 1],
            ..Cond::default()
        },
        actions,
    }
}

/// One atom `drained` (0); a level starting at `level`; `spill` spends 1 while the level is at least 1;
/// `seal` needs the level at most `below` and makes `drained` true. Every state on the way to the goal
/// has the same atoms as the first and less of the level: each is dominated by the one before it.
pub fn tank(level: f64, below: f64) -> GroundTask {
    let mut spill = action(
        "spill",
        Vec::new(),
        vec![ge(0, 1.0)],
        Vec::new(),
        Vec::new(),
    );
    spill.start.num.push(NumEffect {
        op: NumOp::Decrease,
        var: 0,
        expr: NumExpr::Const(1.0),
    });
    let seal = action(
        "seal",
        Vec::new(),
        vec![NumCond {
            cmp: Cmp::Le,
            lhs: NumExpr::Var(0),
            rhs: NumExpr::Const(below),
        }],
        vec![0],
        Vec::new(),
    );
    GroundTask {
        atoms: vec!["(drained)".into()],
        init: Vec::new(),
        nums: vec!["(level)".into()],
        init_nums: vec![level],
        goal: Cond {
            pos: vec![0],
            ..Cond::default()
        },
        actions: vec![spill, seal],
    }
}
