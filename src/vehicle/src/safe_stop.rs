//! Leaving the vehicle safe when the companion stops (a signal): the running actions are ended as `END`
//! ends them, then the mode the configuration names (`modes.on_shutdown`: HOLD by default, RTL, or none)
//! is commanded and confirmed by the vehicle's own HEARTBEAT, not only by the command's ACK (an ACK can be
//! lost, and a HEARTBEAT in the mode is what the vehicle does). Pure: the driver feeds it.

use serde::{Deserialize, Serialize};

use super::commands::CommandOutcome;
use super::config::Mode;

/// What the companion does with the vehicle when it is stopped by a signal.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum OnShutdown {
    /// End the running actions and command HOLD.
    #[default]
    Hold,
    /// End the running actions and command RTL.
    Rtl,
    /// Leave the vehicle as it is (actions keep running on the autopilot).
    None,
}

/// How a safe stop ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SafeStopOutcome {
    /// A HEARTBEAT received after the command shows the mode.
    Confirmed,
    /// ACCEPTED, but no HEARTBEAT in the mode before the wait ended.
    Acknowledged,
    /// The autopilot answered the command with an error.
    Refused,
    /// No ACK and no HEARTBEAT in the mode, after the command's retries.
    NoAnswer,
    /// No autopilot was ever heard from: nothing to command.
    NoVehicle,
    /// `on_shutdown = "none"`: the vehicle left as it was.
    LeftAsIs,
}

impl std::fmt::Display for SafeStopOutcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SafeStopOutcome::Confirmed => "confirmed",
            SafeStopOutcome::Acknowledged => "acknowledged, mode not seen",
            SafeStopOutcome::Refused => "refused by the autopilot",
            SafeStopOutcome::NoAnswer => "no answer",
            SafeStopOutcome::NoVehicle => "no vehicle heard",
            SafeStopOutcome::LeftAsIs => "vehicle left as it was",
        })
    }
}

impl std::fmt::Display for OnShutdown {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            OnShutdown::Hold => "HOLD",
            OnShutdown::Rtl => "RTL",
            OnShutdown::None => "nothing",
        })
    }
}

/// What the safe stop did: the mission report's `shutdown`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SafeStopReport {
    pub action: OnShutdown,
    /// The custom mode commanded (HEARTBEAT.custom_mode), if one was.
    pub mode: Option<u32>,
    /// The tasks of the actions that were running, ended.
    pub stopped: Vec<String>,
    pub outcome: SafeStopOutcome,
    /// The command's answer, when there was one (`ACCEPTED`, `DENIED`, …).
    pub ack: Option<String>,
    /// The vehicle's custom mode in the last HEARTBEAT received.
    pub last_mode: Option<u32>,
}

/// A safe stop under way.
#[derive(Debug, Clone)]
pub struct SafeStop {
    action: OnShutdown,
    mode: Option<Mode>,
    stopped: Vec<String>,
    ack: Option<CommandOutcome>,
    /// A HEARTBEAT after the command showed the mode.
    seen: bool,
    last_mode: Option<u32>,
    /// Settled before anything was sent (no vehicle, nothing to do).
    at_once: Option<SafeStopOutcome>,
}

impl SafeStop {
    /// Commanding `mode` after ending `stopped`.
    pub fn commanding(action: OnShutdown, mode: Mode, stopped: Vec<String>) -> Self {
        SafeStop {
            action,
            mode: Some(mode),
            stopped,
            ack: None,
            seen: false,
            last_mode: None,
            at_once: None,
        }
    }

    /// Nothing sent: `outcome` is final.
    pub fn settled(action: OnShutdown, outcome: SafeStopOutcome) -> Self {
        SafeStop {
            action,
            mode: None,
            stopped: Vec::new(),
            ack: None,
            seen: false,
            last_mode: None,
            at_once: Some(outcome),
        }
    }

    pub fn on_ack(&mut self, outcome: CommandOutcome) {
        self.ack = Some(outcome);
    }

    pub fn on_heartbeat(&mut self, custom_mode: u32) {
        self.last_mode = Some(custom_mode);
        if self.mode.is_some_and(|m| m.custom_mode() == custom_mode) {
            self.seen = true;
        }
    }

    /// The outcome once there is no point waiting longer.
    pub fn outcome(&self) -> Option<SafeStopOutcome> {
        if let Some(o) = self.at_once {
            return Some(o);
        }
        if self.seen {
            return Some(SafeStopOutcome::Confirmed);
        }
        match self.ack {
            Some(CommandOutcome::Rejected(_)) => Some(SafeStopOutcome::Refused),
            Some(CommandOutcome::TimedOut { .. }) => Some(SafeStopOutcome::NoAnswer),
            // ACCEPTED, or nothing yet: the HEARTBEAT may still come.
            _ => None,
        }
    }

    /// The report, now: a wait that ended unsettled is `Acknowledged` after an ACCEPTED, else `NoAnswer`.
    pub fn report(&self) -> SafeStopReport {
        let outcome = self.outcome().unwrap_or(match self.ack {
            Some(CommandOutcome::Accepted) => SafeStopOutcome::Acknowledged,
            _ => SafeStopOutcome::NoAnswer,
        });
        SafeStopReport {
            action: self.action,
            mode: self.mode.map(|m| m.custom_mode()),
            stopped: self.stopped.clone(),
            outcome,
            ack: self.ack.as_ref().map(|a| match a {
                CommandOutcome::Accepted => "ACCEPTED".to_string(),
                CommandOutcome::Rejected(r) => format!("{r:?}"),
                CommandOutcome::TimedOut { tries } => format!("no ACK after {tries} tries"),
            }),
            last_mode: self.last_mode,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::ardupilotmega::MavResult;

    #[test]
    fn confirmed_by_a_heartbeat_in_the_mode_even_without_an_ack() {
        let mut s = SafeStop::commanding(OnShutdown::Hold, Mode::Number(4), vec!["move".into()]);
        assert_eq!(s.outcome(), None);
        s.on_heartbeat(15);
        assert_eq!(s.outcome(), None);
        s.on_ack(CommandOutcome::Accepted);
        assert_eq!(s.outcome(), None, "an ACK alone: wait for the HEARTBEAT");
        assert_eq!(s.report().outcome, SafeStopOutcome::Acknowledged);
        s.on_heartbeat(4);
        let r = s.report();
        assert_eq!(r.outcome, SafeStopOutcome::Confirmed);
        assert_eq!((r.mode, r.last_mode), (Some(4), Some(4)));
        assert_eq!(r.stopped, vec!["move".to_string()]);
    }

    #[test]
    fn refusals_and_silence_are_reported_as_such() {
        let mut s = SafeStop::commanding(OnShutdown::Rtl, Mode::Number(11), Vec::new());
        assert_eq!(s.report().outcome, SafeStopOutcome::NoAnswer);
        s.on_ack(CommandOutcome::Rejected(MavResult::MAV_RESULT_DENIED));
        let r = s.report();
        assert_eq!(r.outcome, SafeStopOutcome::Refused);
        assert_eq!(r.ack.as_deref(), Some("MAV_RESULT_DENIED"));
        let s = SafeStop::settled(OnShutdown::None, SafeStopOutcome::LeftAsIs);
        assert_eq!(s.outcome(), Some(SafeStopOutcome::LeftAsIs));
    }
}
