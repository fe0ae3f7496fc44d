//! `--http ADDR [--http-goals]`: the live page of a mission (src/report/live.rs), shared by `demo` and
//! `run`.

use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use clap::Args;

use crate::cli::out::outln;
use crate::exec::interrupt::Interrupt;
use crate::exec::pacer::StepGate;
use crate::report::live::{GoalCancelFn, GoalForm, PictureGoal};
use crate::vehicle::geo::Home;
use crate::vehicle::goal_client::{replace_goals, send_goals_signed, GCS_SYSTEM_ID};
use crate::vehicle::held::WithdrawError;
use crate::vehicle::intake::GoalIntake;

#[derive(Args, Debug, Clone, Default)]
pub struct HttpArg {
    /// Serve the live page (plan with a now-line, resources against bounds, goals, last events) at ADDR,
    /// e.g. 127.0.0.1:8080 (port 0: any free port; the address is printed). Keep it on loopback unless
    /// the page must be reachable from elsewhere.
    #[arg(long, value_name = "ADDR")]
    pub http: Option<SocketAddr>,
    /// Enable the page's goal form: a goal submitted there is uploaded to the companion's ground station
    /// endpoint, through the same acceptance test as any MAVLink upload.
    #[arg(long, requires = "http")]
    pub http_goals: bool,
}

/// The live page asked for.
#[derive(Clone, Debug)]
pub struct HttpSpec {
    pub addr: SocketAddr,
    pub goals: bool,
}

impl HttpArg {
    pub fn spec(&self) -> Option<HttpSpec> {
        self.http.map(|addr| HttpSpec {
            addr,
            goals: self.http_goals,
        })
    }
}

/// How long the form waits for the intake's verdicts.
const UPLOAD_TIMEOUT: Duration = Duration::from_secs(60);

/// The goal form: a picture goal uploaded over MAVLink to `gcs` (a client address such as
/// `tcpout:127.0.0.1:5760`). `gate`: a stepped simulator waits for the batch (as for the demo's uploads).
/// `signing`: the companion's MAVLink2 signing key and link id, when its config has one. `intake`: the
/// companion's goal intake, to withdraw a goal a station holds by uploading that station's list without it.
pub fn goal_form(
    home: Home,
    gcs: String,
    gate: Option<Arc<StepGate>>,
    signing: Option<([u8; 32], u8)>,
    intake: Option<Arc<Mutex<GoalIntake>>>,
) -> GoalForm {
    let cancel = intake.map(|intake| cancel_path(intake, gcs.clone(), signing));
    GoalForm {
        cancel,
        items: Arc::new(move |g: &PictureGoal| {
            super::demo::picture_goal(home, g.east, g.north, g.window_end_s, g.d_achiev_s).to_vec()
        }),
        submit: Arc::new(move |items| {
            let gcs = gcs.clone();
            let gate = gate.clone();
            Box::pin(async move {
                if let Some(g) = &gate {
                    g.expect_goal_batch();
                }
                let r =
                    send_goals_signed(GCS_SYSTEM_ID, signing, &gcs, items, UPLOAD_TIMEOUT).await;
                // An upload that failed or was refused (MISSION_ACK not accepted) never reached the
                // executive: the stepped simulator stops waiting for it.
                let reached = matches!(&r, Ok(report) if report.failure.is_none());
                if let (false, Some(g)) = (reached, &gate) {
                    g.cancel_goal_batch();
                }
                r
            })
        }),
    }
}

/// Withdraws goal `name` as the mission protocol does: the list of the station that holds it is uploaded
/// again without it, as that station (the intake then cancels it, the executive withdraws it from the plan).
fn cancel_path(
    intake: Arc<Mutex<GoalIntake>>,
    gcs: String,
    signing: Option<([u8; 32], u8)>,
) -> GoalCancelFn {
    Arc::new(move |name: String| {
        let list = match intake.lock() {
            Ok(i) => i.held().list_without(&name),
            Err(_) => Err(WithdrawError::NotHeld(name)),
        };
        let gcs = gcs.clone();
        Box::pin(async move {
            let (station, items) = list?;
            Ok(replace_goals(station, signing, &gcs, items, UPLOAD_TIMEOUT).await?)
        })
    })
}

/// After the mission: the page keeps showing its end until a signal.
pub fn linger(addr: &SocketAddr, interrupt: &Interrupt) {
    outln!("mission over; the page stays at http://{addr}/ until interrupted (Ctrl-C)");
    while interrupt.requested().is_none() {
        std::thread::sleep(Duration::from_millis(100));
    }
}
