//! Waiting for the autopilot to be ready before the mission's first start: a position fix, then arming
//! accepted. A real ArduPilot refuses to arm for ~20 s after boot (EKF, GPS, "PreArm: ..." texts) and
//! reads lat = lon = 0 until its GPS has a fix; a mission started earlier fails its first move and loses
//! every goal with it. ARM is retried with a backoff in the vehicle's time (so a simulator at N× gets its
//! retries in its own time) until accepted or the time limit passes; the autopilot's refusals (COMMAND_ACK
//! and its STATUSTEXTs) are kept as the reason. Pure: the driver feeds it.

use serde::Serialize;

use super::commands::CommandOutcome;

/// First pause between two ARM attempts (vehicle ms); doubled after each refusal up to [`MAX_BACKOFF_MS`].
const FIRST_BACKOFF_MS: u64 = 1_000;
const MAX_BACKOFF_MS: u64 = 8_000;
/// STATUSTEXTs kept as reasons (the newest).
const MAX_REASONS: usize = 6;

/// Where the wait stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReadyPhase {
    /// No position from the autopilot yet (GLOBAL_POSITION_INT absent or at lat = lon = 0).
    WaitingForFix,
    /// An ARM command is out, its answer awaited.
    Arming,
    /// The last ARM was refused; the next goes out at the given vehicle time.
    Backoff(u64),
    /// Armed: the mission can start.
    Ready,
}

/// What the wait did: for the mission report and the message of a failed start.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReadyReport {
    pub ready: bool,
    /// Vehicle ms from the wait's start to the fix, and to arming accepted.
    pub fix_after_ms: Option<u64>,
    pub armed_after_ms: Option<u64>,
    pub arm_attempts: u32,
    /// The autopilot's answers to the refused attempts and its warnings meanwhile, newest last.
    pub refusals: Vec<String>,
}

impl ReadyReport {
    /// Why the vehicle is not ready, in one line (for an error exit).
    pub fn why_not(&self, waited_s: f64) -> String {
        let what = if self.fix_after_ms.is_none() {
            "no position fix (GLOBAL_POSITION_INT still at 0, 0)".to_string()
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
    report: ReadyReport,
}

/// What the driver must do next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadyAction {
    Nothing,
    /// Send MAV_CMD_COMPONENT_ARM_DISARM (arm).
    Arm,
}

impl Readiness {
    pub fn new(vnow: u64) -> Self {
        Readiness {
            phase: ReadyPhase::WaitingForFix,
            started_ms: vnow,
            backoff_ms: FIRST_BACKOFF_MS,
            report: ReadyReport {
                ready: false,
                fix_after_ms: None,
                armed_after_ms: None,
                arm_attempts: 0,
                refusals: Vec::new(),
            },
        }
    }

    pub fn phase(&self) -> ReadyPhase {
        self.phase
    }

    pub fn report(&self) -> &ReadyReport {
        &self.report
    }

    /// Time passed (vehicle ms) with what telemetry shows: a fix, and whether the vehicle is armed.
    pub fn tick(&mut self, vnow: u64, has_fix: bool, armed: bool) -> ReadyAction {
        let since = vnow.saturating_sub(self.started_ms);
        if armed && self.phase != ReadyPhase::Ready {
            // Armed by someone else, or our ACK lost: the vehicle shows it.
            self.report.fix_after_ms.get_or_insert(since);
            self.ready(since);
            return ReadyAction::Nothing;
        }
        match self.phase {
            ReadyPhase::WaitingForFix if has_fix => {
                self.report.fix_after_ms = Some(since);
                self.attempt()
            }
            ReadyPhase::Backoff(at) if vnow >= at => self.attempt(),
            _ => ReadyAction::Nothing,
        }
    }

    fn attempt(&mut self) -> ReadyAction {
        self.report.arm_attempts += 1;
        self.phase = ReadyPhase::Arming;
        ReadyAction::Arm
    }

    fn ready(&mut self, since: u64) {
        self.phase = ReadyPhase::Ready;
        self.report.ready = true;
        self.report.armed_after_ms.get_or_insert(since);
    }

    /// The ARM command's outcome.
    pub fn on_arm(&mut self, vnow: u64, outcome: CommandOutcome, armed: bool) {
        if self.phase != ReadyPhase::Arming {
            return;
        }
        let since = vnow.saturating_sub(self.started_ms);
        match outcome {
            CommandOutcome::Accepted => self.ready(since),
            _ if armed => self.ready(since),
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
        // The same reason repeats at every attempt: keep it once, moved to the end.
        self.report.refusals.retain(|r| r != text);
        self.note(text.to_string());
    }

    fn note(&mut self, reason: String) {
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

    #[test]
    fn arms_only_after_a_fix_and_backs_off_after_refusals() {
        let mut r = Readiness::new(1_000);
        assert_eq!(r.tick(2_000, false, false), ReadyAction::Nothing);
        assert_eq!(r.tick(3_000, true, false), ReadyAction::Arm);
        assert_eq!(r.report().fix_after_ms, Some(2_000));
        r.on_arm(
            3_100,
            CommandOutcome::Rejected(MavResult::MAV_RESULT_FAILED),
            false,
        );
        r.on_text("PreArm: EKF3 waiting for GPS config data");
        assert_eq!(r.phase(), ReadyPhase::Backoff(4_100));
        assert_eq!(r.tick(4_000, true, false), ReadyAction::Nothing);
        assert_eq!(r.tick(4_100, true, false), ReadyAction::Arm);
        r.on_arm(
            4_200,
            CommandOutcome::Rejected(MavResult::MAV_RESULT_FAILED),
            false,
        );
        // The second pause is twice the first.
        assert_eq!(r.phase(), ReadyPhase::Backoff(6_200));
        r.tick(6_200, true, false);
        r.on_arm(6_300, CommandOutcome::Accepted, true);
        assert!(r.report().ready);
        assert_eq!(r.report().arm_attempts, 3);
        assert_eq!(r.report().armed_after_ms, Some(5_300));
        assert!(r.report().refusals.iter().any(|t| t.contains("EKF3")));
    }

    #[test]
    fn the_backoff_is_capped_and_reasons_are_bounded() {
        let mut r = Readiness::new(0);
        let mut t = 0;
        r.tick(t, true, false);
        for i in 0..20 {
            r.on_arm(
                t,
                CommandOutcome::Rejected(MavResult::MAV_RESULT_FAILED),
                false,
            );
            r.on_text(&format!("PreArm: reason {i}"));
            let ReadyPhase::Backoff(at) = r.phase() else {
                panic!("not backing off: {:?}", r.phase());
            };
            assert!(at - t <= MAX_BACKOFF_MS);
            t = at;
            assert_eq!(r.tick(t, true, false), ReadyAction::Arm);
        }
        assert!(r.report().refusals.len() <= MAX_REASONS);
        assert!(!r.report().ready);
        let why = r.report().why_not(60.0);
        assert!(why.contains("arming refused 21 times"), "{why}");
        assert!(why.contains("PreArm: reason 19"), "{why}");
    }

    #[test]
    fn a_vehicle_already_armed_is_ready_without_a_command() {
        let mut r = Readiness::new(0);
        assert_eq!(r.tick(500, true, true), ReadyAction::Nothing);
        assert!(r.report().ready);
        assert_eq!(r.report().arm_attempts, 0);
    }

    #[test]
    fn no_fix_is_said_as_such() {
        let r = Readiness::new(0);
        let why = r.report().why_not(30.0);
        assert!(why.contains("no position fix"), "{why}");
    }
}
