//! Waiting for the autopilot to be ready before the mission's first start: a position fix and a home (the
//! autopilot's estimator trusts its position: ArduPilot sets home only then, and refuses GUIDED before, with
//! "Flight mode change failed", even once armed), then arming accepted. A real ArduPilot refuses to arm
//! for ~20 s after boot (EKF, GPS, "Arm: ..." texts) and reads lat = lon = 0 until its GPS has a fix; a
//! mission started earlier fails its first move and loses every goal with it. ARM is retried with a backoff in the vehicle's time (so a simulator at N× gets its
//! retries in its own time) until accepted or the time limit passes; the autopilot's refusals (COMMAND_ACK
//! and its STATUSTEXTs) are kept as the reason. Pure: the driver feeds it.

use serde::Serialize;

use super::commands::CommandOutcome;

/// First pause between two ARM attempts (vehicle ms); doubled after each refusal up to [`MAX_BACKOFF_MS`].
const FIRST_BACKOFF_MS: u64 = 1_000;
const MAX_BACKOFF_MS: u64 = 8_000;
/// STATUSTEXTs kept as reasons (the newest).
const MAX_REASONS: usize = 6;
/// How often (vehicle ms) HOME_POSITION and the estimator's status are asked for while waiting for them.
const STATUS_REQUEST_MS: u64 = 1_000;

/// What telemetry shows, for the wait.
#[derive(Debug, Clone, Copy, Default)]
pub struct Seen {
    /// A position (GLOBAL_POSITION_INT not at 0, 0).
    pub position: bool,
    /// A home (HOME_POSITION).
    pub home: bool,
    pub armed: bool,
    /// The estimator trusts its horizontal position (ArduPilot's EKF_STATUS_REPORT: absolute position, not
    /// in constant-position mode); `None` when the autopilot does not say.
    pub navigation: Option<bool>,
    /// The autopilot's own pre-arm verdict (PX4's SYS_STATUS PREARM_CHECK health bit, src/vehicle/src/px4.rs);
    /// `None` when it is not read (ArduPilot).
    pub prearm: Option<bool>,
}

/// Where the wait stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReadyPhase {
    /// No position from the autopilot yet (GLOBAL_POSITION_INT absent or at lat = lon = 0), or no home.
    WaitingForFix,
    /// An ARM command is out, its answer awaited.
    Arming,
    /// The last ARM was refused; the next goes out at the given vehicle time.
    Backoff(u64),
    /// A fix, but the autopilot says its pre-arm checks fail (PX4: "heading estimate not stable" for a while
    /// after boot): ARM waits for them to pass, and is tried at the given vehicle time anyway, since PX4
    /// tells its reasons ("Preflight Fail: ...") only on an attempt.
    WaitingForChecks(u64),
    /// Armed, but the estimator does not trust its position yet (GUIDED would be refused).
    WaitingForNavigation,
    /// A fix, and arming is the operator's (`[authority] arm = "operator"`): waiting for them to arm.
    WaitingForOperator,
    /// Armed and navigating: the mission can start.
    Ready,
}

/// What the wait did: for the mission report and the message of a failed start.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReadyReport {
    pub ready: bool,
    /// Vehicle ms from the wait's start to the fix, and to arming accepted.
    pub fix_after_ms: Option<u64>,
    pub armed_after_ms: Option<u64>,
    /// ... and to the estimator trusting its position (the mission's start).
    pub navigation_after_ms: Option<u64>,
    pub arm_attempts: u32,
    /// The autopilot's pre-arm checks failed when last seen (PX4's SYS_STATUS), unarmed.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub checks_failing: bool,
    /// A fix and a home, but the estimator did not trust its position when last seen (a wait that sends no
    /// ARM: `[ready] arm = false`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub navigation_untrusted: bool,
    /// The autopilot's answers to the refused attempts and its warnings meanwhile, newest last.
    pub refusals: Vec<String>,
}

impl ReadyReport {
    /// Why the vehicle is not ready, in one line (for an error exit).
    pub fn why_not(&self, waited_s: f64) -> String {
        let what = if self.fix_after_ms.is_none() {
            "no position fix (GLOBAL_POSITION_INT at 0, 0, or no HOME_POSITION)".to_string()
        } else if self.armed_after_ms.is_some() || self.navigation_untrusted {
            "the estimator does not trust its position (EKF_STATUS_REPORT, PX4's ESTIMATOR_STATUS)"
                .to_string()
        } else if self.checks_failing {
            format!(
                "the autopilot's pre-arm checks fail (SYS_STATUS PREARM_CHECK), {} ARM attempts",
                self.arm_attempts
            )
        } else if self.arm_attempts == 0 {
            "not armed (arming is the operator's: [authority] arm = \"operator\")".to_string()
        } else {
            format!("arming refused {} times", self.arm_attempts)
        };
        let said = if self.refusals.is_empty() {
            String::new()
        } else {
            format!("; the autopilot said: {}", self.refusals.join(" | "))
        };
        format!("the vehicle was not ready after {waited_s:.0} s: {what}{said}")
    }
}

/// The wait under way.
#[derive(Debug, Clone)]
pub struct Readiness {
    phase: ReadyPhase,
    started_ms: u64,
    backoff_ms: u64,
    /// When (vehicle ms) HOME_POSITION and the estimator's status were last asked for.
    status_asked: Option<u64>,
    report: ReadyReport,
    /// Arming is the operator's: no ARM is ever sent.
    operator_arms: bool,
    /// Ready with a fix, a home and the estimator's position, disarmed: a copter arms at its takeoff
    /// (ArduCopter disarms a copter armed on the ground after DISARM_DELAY, 10 s).
    fix_only: bool,
}

/// What the driver must do next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadyAction {
    Nothing,
    /// Send MAV_CMD_COMPONENT_ARM_DISARM (arm).
    Arm,
    /// Ask for HOME_POSITION (sent once home is set) and the estimator's status (MAV_CMD_REQUEST_MESSAGE).
    RequestStatus,
    /// Tell the operator the vehicle waits for them to arm it (once).
    AskOperator,
}

impl Readiness {
    pub fn new(vnow: u64) -> Self {
        Readiness {
            phase: ReadyPhase::WaitingForFix,
            started_ms: vnow,
            backoff_ms: FIRST_BACKOFF_MS,
            status_asked: None,
            operator_arms: false,
            fix_only: false,
            report: ReadyReport {
                ready: false,
                fix_after_ms: None,
                armed_after_ms: None,
                navigation_after_ms: None,
                arm_attempts: 0,
                checks_failing: false,
                navigation_untrusted: false,
                refusals: Vec::new(),
            },
        }
    }

    /// Arming is left to the operator: the wait never sends ARM, it waits for the vehicle armed.
    pub fn operator_arms(mut self) -> Self {
        self.operator_arms = true;
        self
    }

    /// Ready once the vehicle has a fix, a home and (if it says) a trusted position; no ARM is sent.
    pub fn fix_only(mut self) -> Self {
        self.fix_only = true;
        self
    }

    pub fn phase(&self) -> ReadyPhase {
        self.phase
    }

    pub fn report(&self) -> &ReadyReport {
        &self.report
    }

    /// Time passed (vehicle ms) with what telemetry shows.
    pub fn tick(&mut self, vnow: u64, seen: Seen) -> ReadyAction {
        let since = vnow.saturating_sub(self.started_ms);
        if self.phase == ReadyPhase::Ready {
            return ReadyAction::Nothing;
        }
        if seen.armed {
            // Armed (by us, by someone else, or our ACK lost: the vehicle shows it); ready once the
            // estimator, if it tells, trusts its position (ArduPilot, armed, refuses GUIDED before).
            self.report.fix_after_ms.get_or_insert(since);
            self.report.armed_after_ms.get_or_insert(since);
            if seen.navigation != Some(false) {
                return self.ready(since);
            }
            self.phase = ReadyPhase::WaitingForNavigation;
        }
        if self.fix_only && seen.position && seen.home {
            self.report.fix_after_ms.get_or_insert(since);
            self.report.navigation_untrusted = seen.navigation == Some(false);
            if !self.report.navigation_untrusted {
                return self.ready(since);
            }
        }
        match self.phase {
            ReadyPhase::WaitingForFix if seen.position && seen.home && !self.fix_only => {
                self.report.fix_after_ms = Some(since);
                self.attempt(vnow, seen, false)
            }
            ReadyPhase::Backoff(at) if vnow >= at => self.attempt(vnow, seen, false),
            ReadyPhase::WaitingForChecks(at) if seen.prearm != Some(false) || vnow >= at => {
                self.attempt(vnow, seen, true)
            }
            ReadyPhase::WaitingForFix | ReadyPhase::WaitingForNavigation
                if self
                    .status_asked
                    .is_none_or(|t| vnow.saturating_sub(t) >= STATUS_REQUEST_MS) =>
            {
                self.status_asked = Some(vnow);
                ReadyAction::RequestStatus
            }
            _ => ReadyAction::Nothing,
        }
    }

    /// Ready `since` ms after the wait began.
    fn ready(&mut self, since: u64) -> ReadyAction {
        self.phase = ReadyPhase::Ready;
        self.report.ready = true;
        self.report.navigation_after_ms = Some(since);
        ReadyAction::Nothing
    }

    /// ARM now, unless the autopilot says its checks fail and it was not waited for (`waited`).
    fn attempt(&mut self, vnow: u64, seen: Seen, waited: bool) -> ReadyAction {
        if self.operator_arms {
            self.phase = ReadyPhase::WaitingForOperator;
            return ReadyAction::AskOperator;
        }
        self.report.checks_failing = seen.prearm == Some(false);
        if self.report.checks_failing && !waited {
            self.phase = ReadyPhase::WaitingForChecks(vnow.saturating_add(MAX_BACKOFF_MS));
            return ReadyAction::Nothing;
        }
        self.report.arm_attempts += 1;
        self.phase = ReadyPhase::Arming;
        ReadyAction::Arm
    }

    /// The ARM command's outcome.
    pub fn on_arm(&mut self, vnow: u64, outcome: CommandOutcome, armed: bool) {
        if self.phase != ReadyPhase::Arming {
            return;
        }
        match outcome {
            // Armed: the next tick, with what telemetry shows of the estimator, says whether it is ready.
            CommandOutcome::Accepted => {
                self.report.armed_after_ms = Some(vnow.saturating_sub(self.started_ms));
                self.phase = ReadyPhase::WaitingForNavigation;
            }
            _ if armed => self.phase = ReadyPhase::WaitingForNavigation,
            CommandOutcome::Rejected(r) => {
                self.note(format!("ARM refused: {}", super::actions::result_name(r)));
                self.back_off(vnow);
            }
            CommandOutcome::TimedOut { tries } => {
                self.note(format!("no answer to ARM after {tries} tries"));
                self.back_off(vnow);
            }
        }
    }

    fn back_off(&mut self, vnow: u64) {
        self.phase = ReadyPhase::Backoff(vnow.saturating_add(self.backoff_ms));
        self.backoff_ms = (self.backoff_ms * 2).min(MAX_BACKOFF_MS);
    }

    /// A STATUSTEXT of warning severity or worse while waiting (ArduPilot's "PreArm: ..." reasons).
    pub fn on_text(&mut self, text: &str) {
        if self.phase == ReadyPhase::Ready || text.is_empty() {
            return;
        }
        self.note(text.to_string());
    }

    /// Keeps a reason once (the same one repeats at every attempt), moved to the end.
    fn note(&mut self, reason: String) {
        self.report.refusals.retain(|r| *r != reason);
        self.report.refusals.push(reason);
        let n = self.report.refusals.len();
        if n > MAX_REASONS {
            self.report.refusals.drain(..n - MAX_REASONS);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::ardupilotmega::MavResult;

    const NOTHING: Seen = Seen {
        position: false,
        home: false,
        armed: false,
        navigation: None,
        prearm: None,
    };
    const FIX: Seen = Seen {
        position: true,
        home: true,
        armed: false,
        navigation: Some(false),
        prearm: None,
    };
    const ARMED: Seen = Seen { armed: true, ..FIX };

    fn refused() -> CommandOutcome {
        CommandOutcome::Rejected(MavResult::MAV_RESULT_FAILED)
    }

    #[test]
    fn arms_after_a_fix_and_a_home_backs_off_after_refusals_and_waits_for_the_estimator() {
        let mut r = Readiness::new(1_000);
        assert_eq!(r.tick(1_500, NOTHING), ReadyAction::RequestStatus);
        assert_eq!(r.tick(2_000, NOTHING), ReadyAction::Nothing);
        // A position without a home is no fix yet: the status is asked for again a second later.
        let no_home = Seen { home: false, ..FIX };
        assert_eq!(r.tick(2_500, no_home), ReadyAction::RequestStatus);
        assert_eq!(r.tick(3_000, FIX), ReadyAction::Arm);
        assert_eq!(r.report().fix_after_ms, Some(2_000));
        r.on_arm(3_100, refused(), false);
        r.on_text("PreArm: EKF3 waiting for GPS config data");
        assert_eq!(r.phase(), ReadyPhase::Backoff(4_100));
        assert_eq!(r.tick(4_000, FIX), ReadyAction::Nothing);
        assert_eq!(r.tick(4_100, FIX), ReadyAction::Arm);
        r.on_arm(4_200, refused(), false);
        // The second pause is twice the first.
        assert_eq!(r.phase(), ReadyPhase::Backoff(6_200));
        assert_eq!(r.tick(6_200, FIX), ReadyAction::Arm);
        r.on_arm(6_300, CommandOutcome::Accepted, false);
        // Armed, but the estimator is still in constant-position mode: not ready, its status asked for.
        assert_eq!(r.tick(6_400, ARMED), ReadyAction::RequestStatus);
        assert!(!r.report().ready);
        let navigating = Seen {
            navigation: Some(true),
            ..ARMED
        };
        assert_eq!(r.tick(9_000, navigating), ReadyAction::Nothing);
        let report = r.report();
        assert!(report.ready);
        assert_eq!(report.arm_attempts, 3);
        assert_eq!(report.armed_after_ms, Some(5_300));
        assert_eq!(report.navigation_after_ms, Some(8_000));
        assert!(report.refusals.iter().any(|t| t.contains("EKF3")));
    }

    #[test]
    fn the_backoff_is_capped_and_reasons_are_bounded() {
        let mut r = Readiness::new(0);
        let mut t = 0;
        assert_eq!(r.tick(t, FIX), ReadyAction::Arm);
        for i in 0..20 {
            r.on_arm(t, refused(), false);
            r.on_text(&format!("PreArm: reason {i}"));
            let ReadyPhase::Backoff(at) = r.phase() else {
                panic!("not backing off: {:?}", r.phase());
            };
            assert!(at - t <= MAX_BACKOFF_MS);
            t = at;
            assert_eq!(r.tick(t, FIX), ReadyAction::Arm);
        }
        assert!(r.report().refusals.len() <= MAX_REASONS);
        assert!(!r.report().ready);
        let why = r.report().why_not(60.0);
        assert!(why.contains("arming refused 21 times"), "{why}");
        assert!(why.contains("PreArm: reason 19"), "{why}");
    }

    #[test]
    fn an_armed_vehicle_whose_autopilot_says_nothing_of_its_estimator_is_ready_at_once() {
        let mut r = Readiness::new(0);
        let armed = Seen {
            navigation: None,
            ..ARMED
        };
        assert_eq!(r.tick(500, armed), ReadyAction::Nothing);
        assert!(r.report().ready);
        assert_eq!(r.report().arm_attempts, 0);
    }

    #[test]
    fn with_operator_arming_no_arm_is_sent_and_the_operators_arming_makes_it_ready() {
        let mut r = Readiness::new(0).operator_arms();
        assert_eq!(r.tick(100, FIX), ReadyAction::AskOperator);
        assert_eq!(r.phase(), ReadyPhase::WaitingForOperator);
        for t in 1..100 {
            assert_ne!(r.tick(100 + t * 500, FIX), ReadyAction::Arm);
        }
        assert!(r.report().why_not(60.0).contains("operator"));
        let armed = Seen {
            navigation: Some(true),
            ..ARMED
        };
        assert_eq!(r.tick(60_000, armed), ReadyAction::Nothing);
        assert!(r.report().ready);
        assert_eq!(r.report().arm_attempts, 0);
    }

    /// PX4 (SYS_STATUS PREARM_CHECK health bit): no ARM while its checks fail, but one every
    /// MAX_BACKOFF_MS so that its "Preflight Fail" reasons are heard; ARM as soon as they pass.
    #[test]
    fn px4_arms_once_its_prearm_checks_pass_and_tries_meanwhile_for_the_reasons() {
        let failing = Seen {
            prearm: Some(false),
            ..FIX
        };
        let passing = Seen {
            prearm: Some(true),
            ..FIX
        };
        let mut r = Readiness::new(0);
        assert_eq!(r.tick(1_000, failing), ReadyAction::Nothing);
        assert_eq!(
            r.phase(),
            ReadyPhase::WaitingForChecks(1_000 + MAX_BACKOFF_MS)
        );
        assert_eq!(r.report().arm_attempts, 0);
        assert!(r.report().why_not(5.0).contains("pre-arm checks fail"));
        assert_ne!(r.tick(5_000, failing), ReadyAction::Arm);
        // Still failing after the longest pause: one attempt, its refusal and reasons kept.
        assert_eq!(r.tick(1_000 + MAX_BACKOFF_MS, failing), ReadyAction::Arm);
        r.on_arm(
            9_100,
            CommandOutcome::Rejected(MavResult::MAV_RESULT_TEMPORARILY_REJECTED),
            false,
        );
        r.on_text("Preflight Fail: heading estimate not stable");
        let ReadyPhase::Backoff(at) = r.phase() else {
            panic!("{:?}", r.phase());
        };
        // Due again but the checks still fail: waits for them.
        assert_eq!(r.tick(at, failing), ReadyAction::Nothing);
        // They pass: ARM at once.
        assert_eq!(r.tick(at + 100, passing), ReadyAction::Arm);
        r.on_arm(at + 200, CommandOutcome::Accepted, true);
        let navigating = Seen {
            armed: true,
            navigation: Some(true),
            ..passing
        };
        assert_eq!(r.tick(at + 300, navigating), ReadyAction::Nothing);
        let rep = r.report();
        assert!(rep.ready);
        assert_eq!(rep.arm_attempts, 2);
        assert!(rep
            .refusals
            .iter()
            .any(|t| t.contains("TEMPORARILY_REJECTED")));
        assert!(rep.refusals.iter().any(|t| t.contains("heading")));
    }

    #[test]
    fn why_not_ready_says_which_step_is_missing() {
        let mut r = Readiness::new(0);
        assert!(r.report().why_not(30.0).contains("no position fix"));
        r.tick(0, FIX);
        r.on_arm(10, CommandOutcome::Accepted, true);
        r.tick(20, ARMED);
        let why = r.report().why_not(30.0);
        assert!(why.contains("estimator"), "{why}");
        // No ARM sent (a copter arms at its takeoff): the estimator is what is missing, not an operator.
        let mut f = Readiness::new(0).fix_only();
        assert_ne!(f.tick(0, FIX), ReadyAction::Arm);
        let why = f.report().why_not(120.0);
        assert!(why.contains("estimator"), "{why}");
        assert!(!why.contains("operator"), "{why}");
        f.tick(
            1_000,
            Seen {
                navigation: Some(true),
                ..FIX
            },
        );
        assert!(f.report().ready);
    }
}
