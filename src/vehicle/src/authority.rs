//! Who commands the vehicle. On ArduPilot and PX4 a mode the companion did not command (an RC switch, a
//! ground station's HOLD, MANUAL, RTL, LOITER, …) or a disarm means a person took control: the companion
//! yields — it sends the vehicle no command until control is handed back, by switching the vehicle back to
//! the companion's mode (GUIDED) armed, or by `MAV_CMD_DO_PAUSE_CONTINUE` (p1 = 1) to component 191.
//! `[authority]` in the vehicle configuration says whether to yield (`on_foreign_mode`), who arms
//! (`arm`) and what the companion leaves the vehicle in at the end of a mission (`at_end`). Pure: the driver
//! feeds it the HEARTBEATs and the modes it commands itself.

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, MavType};
use serde::{Deserialize, Serialize};

use super::config::{Autopilot, Modes};

/// `[authority]`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AuthorityConfig {
    #[serde(default)]
    pub on_foreign_mode: OnForeignMode,
    #[serde(default)]
    pub arm: Arming,
    #[serde(default)]
    pub at_end: AtEnd,
}

/// What a mode the companion did not command does.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum OnForeignMode {
    /// The companion yields until control is handed back (the autopilots' convention).
    #[default]
    Pause,
    /// The running motion fails and the plan is repaired at once (the companion takes control back).
    Repair,
}

/// Who arms the vehicle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Arming {
    /// The companion arms it before the mission and when a motion starts disarmed (simulators).
    #[default]
    Companion,
    /// The operator arms it: the companion waits, and never sends ARM.
    Operator,
}

/// What the companion leaves the vehicle in when the mission ends.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AtEnd {
    /// HOLD, then disarm once it holds.
    #[default]
    HoldDisarm,
    /// HOLD, armed.
    Hold,
    /// As it is.
    None,
}

/// A change of who commands the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub enum Change {
    /// The companion yields; `why` in the operator's words (e.g. "the vehicle was switched to HOLD").
    Paused { why: String },
    /// Control handed back; `how` in the operator's words.
    Resumed { how: String },
}

/// What the executive is told.
#[derive(Debug, Clone, PartialEq)]
pub enum AuthorityEvent {
    /// The companion yields: the running actions were ended (their reports follow), no command goes out.
    Paused { why: String },
    /// Control handed back; where the vehicle is now (metres from the configuration's home).
    Resumed {
        how: String,
        position: Option<super::types::Enu>,
        /// Within this distance the vehicle is where the plan has it ([`start_radius_m`]).
        radius_m: f64,
    },
}

/// How far the vehicle may be from the plan's place and still be there: the largest acceptance radius of
/// the configuration's moves (2 m without one).
pub fn start_radius_m(cfg: &super::config::VehicleConfig) -> f64 {
    cfg.actions
        .values()
        .filter_map(|b| match b {
            super::config::Binding::Move {
                acceptance_radius_m,
                ..
            } => Some(*acceptance_radius_m),
            _ => None,
        })
        .fold(None, |m: Option<f64>, r| Some(m.map_or(r, |m| m.max(r))))
        .unwrap_or(2.0)
}

/// How long (vehicle ms) a disarm waits for the restart that would explain it before it is the operator's.
pub const DISARM_GRACE_MS: u64 = 1_500;

/// The companion's view of who commands the vehicle.
#[derive(Debug, Clone)]
pub struct Authority {
    cfg: AuthorityConfig,
    /// The companion's driving mode (GUIDED): a switch to it hands control back.
    own_mode: u32,
    /// Modes in which a flying vehicle lands and disarms itself (`[modes] land` and RTL, when the
    /// vehicle has a landing mode).
    landing_modes: Vec<u32>,
    /// The modes the companion commanded and may see next (the last one, and the one before while the
    /// vehicle has not switched yet).
    expected: Vec<u32>,
    /// The companion has seen the vehicle in a mode it commanded: from then on a foreign mode is the
    /// operator's.
    in_control: bool,
    paused: bool,
    last_mode: Option<u32>,
    armed: bool,
    disarmed_since: Option<u64>,
    /// When (vehicle ms) the autopilot last reported an error (STATUSTEXT ERROR or worse).
    error_at: Option<u64>,
    /// The mission is over: the companion's own end-of-mission HOLD and disarm take no control back.
    released: bool,
    /// The autopilot's vehicle type, once its HEARTBEAT said.
    vehicle: Option<MavType>,
    /// Disarmed by a landing, not armed since: the mode PX4 switches to once disarmed (the last one
    /// that allows arming, UserModeIntention::onDisarm) is the autopilot's, not an operator's.
    landed_disarmed: bool,
}

/// A mode change this soon (vehicle ms) after an autopilot error is the autopilot's own reaction (a
/// failsafe HOLD after "Navigation failed"): the failed motion is repaired, nobody took control.
pub const AUTOPILOT_REACTION_MS: u64 = 2_000;

impl Authority {
    pub fn new(cfg: AuthorityConfig, modes: &Modes) -> Self {
        Authority {
            cfg,
            own_mode: modes.guided.custom_mode(),
            landing_modes: modes
                .land
                .map(|l| vec![l.custom_mode(), modes.rtl.custom_mode()])
                .unwrap_or_default(),
            expected: Vec::new(),
            in_control: false,
            paused: false,
            last_mode: None,
            armed: false,
            disarmed_since: None,
            error_at: None,
            released: false,
            vehicle: None,
            landed_disarmed: false,
        }
    }

    /// The autopilot reported an error (its own mode change may follow).
    pub fn on_error_text(&mut self, vnow: u64) {
        self.error_at = Some(vnow);
    }

    pub fn config(&self) -> AuthorityConfig {
        self.cfg
    }

    /// The companion yields (no command goes to the vehicle).
    pub fn is_paused(&self) -> bool {
        self.paused
    }

    /// The companion commanded `mode` (custom mode number).
    pub fn commanded(&mut self, mode: u32) {
        if self.expected.last() != Some(&mode) {
            // The mode before stays expected until the vehicle shows the new one.
            let keep = self.last_mode.filter(|m| self.expected.contains(m));
            self.expected.clear();
            self.expected.extend(keep);
            self.expected.push(mode);
        }
    }

    /// A HEARTBEAT of the autopilot at vehicle time `vnow`.
    pub fn on_heartbeat(&mut self, mode: u32, armed: bool, vnow: u64) -> Option<Change> {
        // Back in the companion's mode, or armed again in it: a hand-over.
        let handed = self.last_mode != Some(mode) || !self.armed;
        self.last_mode = Some(mode);
        self.armed = armed;
        if armed {
            self.disarmed_since = None;
            self.landed_disarmed = false;
        } else if self.landing_modes.contains(&mode) || self.landed_disarmed {
            // A multicopter that lands disarms itself (ArduCopter's ModeLand and RTL, PX4's AUTO.LAND and
            // AUTO.RTL, which then switches to the mode before them): not the operator.
            self.disarmed_since = None;
            self.landed_disarmed = true;
        } else if self.in_control
            && !self.paused
            && self.cfg.on_foreign_mode == OnForeignMode::Pause
        {
            // A disarm is the operator's only once no restart explains it (see `on_tick`).
            self.disarmed_since.get_or_insert(vnow);
        }
        if self.expected.last() == Some(&mode) {
            // The vehicle took the companion's last command: the one before is history.
            self.expected.retain(|&m| m == mode);
        }
        if self.paused {
            return (armed && mode == self.own_mode && handed).then(|| {
                self.resume(format!("the vehicle is back in {}, armed", self.name(mode)))
            });
        }
        if self.expected.contains(&mode) {
            self.in_control |= armed && !self.released;
            return None;
        }
        // A switch into the companion's own mode is a hand-over, never a taking of control.
        if !self.in_control || mode == self.own_mode || !armed {
            return None;
        }
        if self
            .error_at
            .is_some_and(|t| vnow.saturating_sub(t) <= AUTOPILOT_REACTION_MS)
        {
            // The autopilot's reaction to its error: the companion repairs from there.
            self.expected = vec![mode];
            return None;
        }
        if self.cfg.on_foreign_mode == OnForeignMode::Repair {
            return None;
        }
        self.pause(format!("the vehicle was switched to {}", self.name(mode)))
    }

    /// Time passed (vehicle ms): a disarm no restart explained pauses.
    pub fn on_tick(&mut self, vnow: u64) -> Option<Change> {
        let since = self.disarmed_since?;
        if self.paused || vnow.saturating_sub(since) < DISARM_GRACE_MS {
            return None;
        }
        self.disarmed_since = None;
        self.pause("the vehicle was disarmed".into())
    }

    /// The autopilot restarted (its clock went back): a disarm at boot is not the operator's.
    pub fn on_restart(&mut self) -> Option<Change> {
        self.disarmed_since = None;
        if self.cfg.arm == Arming::Operator
            && self.cfg.on_foreign_mode == OnForeignMode::Pause
            && self.in_control
            && !self.paused
        {
            // The companion would have to arm it again, and arming is the operator's.
            return self.pause("the autopilot restarted disarmed; arming is the operator's".into());
        }
        // The companion commands its runs again (arming, its mode): the boot mode seen meanwhile is not
        // the operator's.
        self.in_control = false;
        self.expected.clear();
        None
    }

    /// `MAV_CMD_DO_PAUSE_CONTINUE` from a ground station: p1 = 1 hands control back (armed), 0 pauses.
    pub fn on_pause_continue(&mut self, cont: bool) -> Result<Option<Change>, &'static str> {
        match (cont, self.paused) {
            (true, true) if !self.armed => Err("the vehicle is not armed"),
            (true, true) => Ok(Some(self.resume("continue (DO_PAUSE_CONTINUE)".into()))),
            (false, false) => Ok(self.pause("pause asked (DO_PAUSE_CONTINUE)".into())),
            _ => Ok(None),
        }
    }

    fn pause(&mut self, why: String) -> Option<Change> {
        self.paused = true;
        self.expected.clear();
        Some(Change::Paused { why })
    }

    fn resume(&mut self, how: String) -> Change {
        self.paused = false;
        self.in_control = true;
        // The vehicle is where the operator left it, in its mode: that mode is no news.
        self.expected = self.last_mode.into_iter().collect();
        Change::Resumed { how }
    }

    /// The companion releases the vehicle (mission over): a later mode change is nobody's business.
    pub fn release(&mut self) {
        self.released = true;
        self.in_control = false;
        self.expected.clear();
        self.disarmed_since = None;
    }

    /// The autopilot's vehicle type (its HEARTBEAT): which table names its modes.
    pub fn set_vehicle_type(&mut self, vehicle: MavType) {
        self.vehicle = Some(vehicle);
    }

    /// The mode's name as the operator knows it.
    fn name(&self, mode: u32) -> String {
        super::mode_names::mode_name(mode, self.vehicle)
    }
}

/// The mode a message of the companion commands, if it commands one: DO_SET_MODE (its params matched
/// against the configuration's modes, else ArduPilot's number in p2), DO_REPOSITION with its
/// change-mode flag (GUIDED).
pub fn commanded_mode(msg: &MavMessage, modes: &Modes, autopilot: Autopilot) -> Option<u32> {
    match msg {
        MavMessage::COMMAND_LONG(c) if c.command == MavCmd::MAV_CMD_DO_SET_MODE => {
            let known = modes
                .by_key()
                .into_iter()
                .find(|(_, m)| m.set_mode_params() == (c.param2, c.param3))
                .map(|(_, m)| m.custom_mode());
            known.or((autopilot == Autopilot::Ardupilot).then_some(c.param2 as u32))
        }
        MavMessage::COMMAND_INT(c)
            if c.command == MavCmd::MAV_CMD_DO_REPOSITION && c.param2 == 1.0 =>
        {
            Some(modes.guided.custom_mode())
        }
        MavMessage::COMMAND_LONG(c)
            if c.command == MavCmd::MAV_CMD_DO_REPOSITION && c.param2 == 1.0 =>
        {
            Some(modes.guided.custom_mode())
        }
        // PX4's Commander switches to AUTO.TAKEOFF on NAV_TAKEOFF (Commander.cpp `VEHICLE_CMD_NAV_TAKEOFF`);
        // once the takeoff is over it loiters (AUTO.LOITER, the companion's own mode) by itself.
        // ArduCopter takes off in the GUIDED it is in.
        MavMessage::COMMAND_LONG(c)
            if c.command == MavCmd::MAV_CMD_NAV_TAKEOFF && autopilot == Autopilot::Px4 =>
        {
            Some(super::flight::PX4_AUTO_TAKEOFF)
        }
        _ => None,
    }
}

/// Whether a message of the companion may go out while it yields: what only reads the vehicle or speaks
/// to people (heartbeats, texts, message requests, a mission download), never what commands it.
pub fn allowed_while_paused(msg: &MavMessage) -> bool {
    match msg {
        MavMessage::COMMAND_LONG(c) => matches!(
            c.command,
            MavCmd::MAV_CMD_REQUEST_MESSAGE | MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL
        ),
        MavMessage::COMMAND_INT(_)
        | MavMessage::MISSION_COUNT(_)
        | MavMessage::MISSION_ITEM_INT(_)
        | MavMessage::MISSION_CLEAR_ALL(_)
        | MavMessage::SET_POSITION_TARGET_LOCAL_NED(_)
        | MavMessage::SET_POSITION_TARGET_GLOBAL_INT(_)
        | MavMessage::MANUAL_CONTROL(_)
        | MavMessage::RC_CHANNELS_OVERRIDE(_) => false,
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::tests::rover_modes as modes;

    fn driving() -> Authority {
        let mut a = Authority::new(AuthorityConfig::default(), &modes());
        assert_eq!(
            a.on_heartbeat(0, false, 0),
            None,
            "MANUAL before the mission"
        );
        assert_eq!(a.on_heartbeat(0, true, 100), None, "armed by the operator");
        a.commanded(15);
        assert_eq!(a.on_heartbeat(0, true, 200), None, "not switched yet");
        assert_eq!(a.on_heartbeat(15, true, 300), None);
        a
    }

    #[test]
    fn a_foreign_hold_pauses_and_guided_armed_resumes() {
        let mut a = driving();
        let Some(Change::Paused { why }) = a.on_heartbeat(4, true, 1_000) else {
            panic!("no pause")
        };
        assert_eq!(why, "the vehicle was switched to HOLD");
        assert!(a.is_paused());
        assert_eq!(a.on_heartbeat(4, true, 2_000), None, "still paused");
        assert_eq!(
            a.on_heartbeat(0, true, 3_000),
            None,
            "MANUAL: still the operator's"
        );
        let Some(Change::Resumed { how }) = a.on_heartbeat(15, true, 9_000) else {
            panic!("no resume")
        };
        assert!(how.contains("GUIDED"), "{how}");
        assert!(!a.is_paused());
        assert_eq!(a.on_heartbeat(15, true, 9_100), None);
    }

    #[test]
    fn the_companions_own_hold_is_no_pause_and_repair_mode_never_pauses() {
        let mut a = driving();
        a.commanded(4);
        assert_eq!(a.on_heartbeat(15, true, 400), None, "HOLD not taken yet");
        assert_eq!(a.on_heartbeat(4, true, 500), None, "our HOLD");
        a.commanded(15);
        assert_eq!(a.on_heartbeat(15, true, 600), None);
        let mut r = Authority::new(
            AuthorityConfig {
                on_foreign_mode: OnForeignMode::Repair,
                ..Default::default()
            },
            &modes(),
        );
        r.commanded(15);
        r.on_heartbeat(15, true, 0);
        assert_eq!(r.on_heartbeat(4, true, 100), None);
    }

    #[test]
    fn a_disarm_pauses_after_its_grace_unless_a_restart_explains_it() {
        let mut a = driving();
        assert_eq!(a.on_heartbeat(15, false, 1_000), None);
        assert_eq!(a.on_tick(1_000 + DISARM_GRACE_MS - 1), None);
        assert!(matches!(
            a.on_tick(1_000 + DISARM_GRACE_MS),
            Some(Change::Paused { .. })
        ));
        // Continue is refused while disarmed, accepted once armed.
        assert!(a.on_pause_continue(true).is_err());
        a.on_heartbeat(15, true, 5_000);
        assert!(!a.is_paused(), "GUIDED and armed again hands control back");
        let mut b = driving();
        b.on_heartbeat(0, false, 1_000);
        assert_eq!(b.on_restart(), None, "the companion arms after a restart");
        assert_eq!(b.on_tick(9_000), None);
    }

    #[test]
    fn the_autopilots_own_hold_after_an_error_is_no_pause() {
        let mut a = driving();
        a.on_error_text(1_000);
        assert_eq!(a.on_heartbeat(4, true, 1_200), None);
        assert!(!a.is_paused());
        a.commanded(15);
        a.on_heartbeat(15, true, 5_000);
        assert!(matches!(
            a.on_heartbeat(4, true, 9_000),
            Some(Change::Paused { .. })
        ));
    }

    /// A PX4 copter's modes (config/px4-copter.toml): custom_mode = main << 16 | sub << 24.
    fn px4_copter_modes() -> Modes {
        use crate::config::Mode;
        let px4 = |main, sub| Mode::Px4 { main, sub };
        Modes {
            hold: px4(4, 3),
            auto: px4(4, 4),
            guided: px4(4, 3),
            rtl: px4(4, 5),
            manual: Some(px4(1, 0)),
            land: Some(px4(4, 6)),
            on_shutdown: Default::default(),
        }
    }

    #[test]
    fn px4s_own_switches_after_a_takeoff_and_a_landing_are_no_pause() {
        use mavlink::dialects::ardupilotmega::COMMAND_LONG_DATA;
        let modes = px4_copter_modes();
        let (hold, land) = (4 << 16 | 3 << 24, 4 << 16 | 6 << 24);
        let takeoff = crate::flight::PX4_AUTO_TAKEOFF;
        let mut a = Authority::new(AuthorityConfig::default(), &modes);
        a.set_vehicle_type(MavType::MAV_TYPE_QUADROTOR);
        a.on_heartbeat(hold, false, 0);
        // In the air, in control (a reposition), then the companion's AUTO.LAND: PX4 lands, disarms, and
        // switches back to Hold, disarmed (UserModeIntention::onDisarm).
        a.commanded(hold);
        a.on_heartbeat(hold, true, 1_000);
        a.commanded(land);
        assert_eq!(a.on_heartbeat(land, true, 2_000), None);
        assert_eq!(a.on_heartbeat(land, false, 30_000), None);
        assert_eq!(a.on_heartbeat(hold, false, 30_500), None);
        assert_eq!(a.on_tick(40_000), None, "the landing's disarm: no pause");
        // The next takeoff: ARM, NAV_TAKEOFF (PX4 enters AUTO.TAKEOFF), then PX4's own loiter.
        let cmd = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            command: MavCmd::MAV_CMD_NAV_TAKEOFF,
            ..Default::default()
        });
        assert_eq!(commanded_mode(&cmd, &modes, Autopilot::Px4), Some(takeoff));
        assert_eq!(commanded_mode(&cmd, &modes, Autopilot::Ardupilot), None);
        a.on_heartbeat(hold, true, 41_000);
        a.commanded(takeoff);
        assert_eq!(a.on_heartbeat(takeoff, true, 41_500), None);
        assert_eq!(a.on_heartbeat(hold, true, 60_000), None);
        assert!(!a.is_paused());
        // An operator's Return is still one, named from PX4's table.
        let Some(Change::Paused { why }) = a.on_heartbeat(4 << 16 | 5 << 24, true, 70_000) else {
            panic!("Return pauses")
        };
        assert_eq!(why, "the vehicle was switched to Return (4/5)");
    }

    #[test]
    fn a_copters_modes_are_named_from_arducopters_table() {
        let mut modes = modes();
        modes.guided = crate::config::Mode::Number(4);
        modes.land = Some(crate::config::Mode::Number(9));
        let mut a = Authority::new(AuthorityConfig::default(), &modes);
        a.set_vehicle_type(MavType::MAV_TYPE_QUADROTOR);
        a.on_heartbeat(4, false, 0);
        a.commanded(4);
        a.on_heartbeat(4, true, 100);
        let Some(Change::Paused { why }) = a.on_heartbeat(6, true, 1_000) else {
            panic!("RTL pauses")
        };
        assert_eq!(why, "the vehicle was switched to RTL");
    }

    #[test]
    fn pause_continue_pauses_and_resumes() {
        let mut a = driving();
        assert!(matches!(
            a.on_pause_continue(false),
            Ok(Some(Change::Paused { .. }))
        ));
        assert!(matches!(
            a.on_pause_continue(true),
            Ok(Some(Change::Resumed { .. }))
        ));
        assert_eq!(a.on_pause_continue(true), Ok(None));
    }

    #[test]
    fn commands_are_held_back_while_paused_but_reads_go_out() {
        use mavlink::dialects::ardupilotmega::{COMMAND_LONG_DATA, HEARTBEAT_DATA};
        let cmd = |command| {
            MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
                command,
                param2: 4.0,
                ..Default::default()
            })
        };
        assert!(!allowed_while_paused(&cmd(MavCmd::MAV_CMD_DO_SET_MODE)));
        assert!(!allowed_while_paused(&cmd(
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM
        )));
        assert!(allowed_while_paused(&cmd(MavCmd::MAV_CMD_REQUEST_MESSAGE)));
        assert!(allowed_while_paused(&MavMessage::HEARTBEAT(
            HEARTBEAT_DATA::default()
        )));
        assert_eq!(
            commanded_mode(
                &cmd(MavCmd::MAV_CMD_DO_SET_MODE),
                &modes(),
                Autopilot::Ardupilot
            ),
            Some(4)
        );
    }
}
