//! A multicopter's flight actions: take off, fly to a place at its altitude, land where it is, return home
//! and land. Pure, like [`super::actions`] whose [`super::actions::Run`] delegates to a [`Flight`]. What each
//! autopilot accepts, from its sources:
//! - ArduCopter (ArduCopter/GCS_MAVLink_Copter.cpp): `handle_MAV_CMD_NAV_TAKEOFF` takes param7 as metres
//!   above home and, over COMMAND_INT, only frame GLOBAL_RELATIVE_ALT (3); over COMMAND_LONG the frame is
//!   implied (`mav_frame_for_command_long`), so takeoff goes as COMMAND_LONG. `do_user_takeoff` needs the
//!   vehicle armed, landed and in a mode with a user takeoff (GUIDED): GUIDED first, then ARM, then the
//!   takeoff, at once (`Copter::auto_disarm_check` disarms a landed copter after DISARM_DELAY, 10 s).
//!   `handle_command_int_do_reposition` reads the frame through `location_from_command_t`:
//!   GLOBAL_RELATIVE_ALT (3, or 6) is altitude above home; with the change-mode bit it enters GUIDED
//!   (mode_guided.cpp `set_destination`). MAV_CMD_NAV_LAND and LAND mode (9) land where it is and
//!   `ModeLand` disarms once landed; RTL (6) climbs to RTL_ALT, flies home and lands (RTL_ALT_FINAL 0).
//!   EXTENDED_SYS_STATE's landed_state is `GCS_MAVLINK_Copter::landed_state` (ON_GROUND once
//!   `land_complete`), but it is in no default stream: it is asked for with SET_MESSAGE_INTERVAL.
//! - PX4 (src/modules/mavlink/mavlink_receiver.cpp `handle_message_command_int`): COMMAND_INT only in
//!   frame GLOBAL_INT (altitude AMSL), else MAV_RESULT 9; navigator_main.cpp: NAV_TAKEOFF's param7 is
//!   the AMSL altitude (`rep->current.alt = cmd.param7`), DO_REPOSITION's too; Commander switches to
//!   AUTO.TAKEOFF on NAV_TAKEOFF, then the navigator loiters (AUTO.LOITER). PX4 streams
//!   EXTENDED_SYS_STATE itself.

use mavlink::dialects::ardupilotmega::{
    MavCmd, MavFrame, MavLandedState, MavMessage, MavModeFlag, COMMAND_INT_DATA,
};

use super::actions::{Ctx, StartError};
use super::commands::{Command, CommandOutcome};
use super::config::{Autopilot, Modes};
use super::types::{ActionStart, Enu};
use geodesy::deg_to_e7;

/// `[actions.<task>]` of kind `takeoff`, `fly_to`, `land` or `return_land`.
#[derive(Debug, Clone, PartialEq)]
pub enum FlightBinding {
    /// GUIDED, armed, MAV_CMD_NAV_TAKEOFF to `altitude_m` above home; done within
    /// `vertical_acceptance_m` of it.
    Takeoff {
        altitude_m: f64,
        vertical_acceptance_m: f64,
    },
    /// DO_REPOSITION to the location argument `to`, at its `up` (metres above home); done within
    /// `acceptance_radius_m` horizontally and `vertical_acceptance_m` vertically.
    FlyTo {
        to: String,
        acceptance_radius_m: f64,
        vertical_acceptance_m: f64,
        speed_m_s: f64,
        position_variable: String,
    },
    /// LAND where it is (`home` false: `[modes] land`), or RTL: home, then land (`home` true, done within
    /// `acceptance_radius_m` of home); done once landed.
    Land {
        home: bool,
        acceptance_radius_m: f64,
        position_variable: String,
    },
}

impl FlightBinding {
    /// The first key that is wrong, and why.
    pub fn invalid(&self, modes: &Modes) -> Option<(&'static str, &'static str)> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        match self {
            FlightBinding::Takeoff {
                altitude_m,
                vertical_acceptance_m,
            } => {
                if !positive(*altitude_m) {
                    return Some(("altitude_m", "metres above home, > 0"));
                }
                if !positive(*vertical_acceptance_m) {
                    return Some(("vertical_acceptance_m", "must be > 0"));
                }
            }
            FlightBinding::FlyTo {
                acceptance_radius_m,
                vertical_acceptance_m,
                ..
            } => {
                if !positive(*acceptance_radius_m) {
                    return Some(("acceptance_radius_m", "must be > 0"));
                }
                if !positive(*vertical_acceptance_m) {
                    return Some(("vertical_acceptance_m", "must be > 0"));
                }
            }
            FlightBinding::Land {
                home,
                acceptance_radius_m,
                ..
            } => {
                if !positive(*acceptance_radius_m) {
                    return Some(("acceptance_radius_m", "must be > 0"));
                }
                if !home && modes.land.is_none() {
                    return Some(("kind", "kind land needs a landing mode: [modes] land"));
                }
            }
        }
        None
    }

    /// The location parameter the binding names (checked against the domain).
    pub fn location_param(&self) -> Option<&str> {
        match self {
            FlightBinding::FlyTo { to, .. } => Some(to),
            _ => None,
        }
    }

    /// The state variable a non-nominal report gives the reached position in.
    pub fn position_variable(&self) -> Option<&str> {
        match self {
            FlightBinding::FlyTo {
                position_variable, ..
            }
            | FlightBinding::Land {
                position_variable, ..
            } => Some(position_variable),
            FlightBinding::Takeoff { .. } => None,
        }
    }
}

/// What telemetry says of a flying vehicle.
#[derive(Debug, Default, Clone)]
pub struct FlightTelemetry {
    /// Metres above home (GLOBAL_POSITION_INT.relative_alt).
    pub relative_alt_m: Option<f64>,
    /// EXTENDED_SYS_STATE.landed_state, once the autopilot sent one.
    pub landed_state: Option<MavLandedState>,
    /// Home's altitude AMSL (HOME_POSITION), metres: PX4 takes altitudes AMSL.
    pub home_amsl_m: Option<f64>,
    /// Position's AMSL altitude minus its altitude above home, metres: home AMSL before HOME_POSITION.
    amsl_offset_m: Option<f64>,
}

impl FlightTelemetry {
    pub fn update(&mut self, msg: &MavMessage) {
        match msg {
            MavMessage::GLOBAL_POSITION_INT(p) if p.lat != 0 || p.lon != 0 => {
                let rel = f64::from(p.relative_alt) / 1000.0;
                self.relative_alt_m = Some(rel);
                self.amsl_offset_m = Some(f64::from(p.alt) / 1000.0 - rel);
            }
            MavMessage::EXTENDED_SYS_STATE(s) => self.landed_state = Some(s.landed_state),
            MavMessage::HOME_POSITION(h) if h.latitude != 0 || h.longitude != 0 => {
                self.home_amsl_m = Some(f64::from(h.altitude) / 1000.0);
            }
            _ => {}
        }
    }

    /// Home's AMSL altitude as the autopilot has it.
    pub fn home_amsl(&self) -> Option<f64> {
        self.home_amsl_m.or(self.amsl_offset_m)
    }

    /// On the ground: EXTENDED_SYS_STATE says so; without it, `armed` false near home's altitude.
    pub fn on_ground(&self, armed: bool) -> bool {
        match self.landed_state {
            Some(s) => s == MavLandedState::MAV_LANDED_STATE_ON_GROUND,
            None => !armed && self.relative_alt_m.is_some_and(|a| a.abs() < 1.0),
        }
    }
}

/// How a flight action ended; [`super::actions::Run`] turns it into a report with the vehicle's state.
#[derive(Debug, Clone, PartialEq)]
pub enum FlightEnd {
    Nominal,
    Failed(String),
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// Waiting for the ACK of the mode change (GUIDED before a takeoff, LAND, RTL).
    Mode,
    Arming,
    /// Waiting for the ACK of the takeoff or the reposition.
    Starting,
    Running,
}

/// One running flight action.
#[derive(Debug, Clone)]
pub struct Flight {
    binding: FlightBinding,
    phase: Phase,
    /// Fly-to destination (up: metres above home); home for a return.
    goal: Option<Enu>,
    /// Modes the vehicle may be in while this runs (the companion's and what the autopilot itself
    /// switches to on the way, e.g. PX4's AUTO.LOITER after AUTO.TAKEOFF).
    modes: Vec<u32>,
    mode_seen: bool,
    /// The vehicle was seen off the ground under this run (a landing is over only after it).
    airborne_seen: bool,
}

/// PX4's AUTO.TAKEOFF (main 4, sub 2: px4_custom_mode.h), entered on NAV_TAKEOFF.
pub const PX4_AUTO_TAKEOFF: u32 = 4 << 16 | 2 << 24;

/// EXTENDED_SYS_STATE, asked for at 2 Hz (ArduCopter does not stream it).
const EXTENDED_SYS_STATE_ID: f32 = 245.0;
const EXTENDED_SYS_STATE_US: f32 = 500_000.0;

impl Flight {
    pub fn begin(
        start: &ActionStart,
        binding: &FlightBinding,
        ctx: &mut Ctx,
    ) -> Result<Self, StartError> {
        let modes = &ctx.cfg.modes;
        let px4 = ctx.cfg.autopilot == Autopilot::Px4;
        let mut f = Flight {
            binding: binding.clone(),
            phase: Phase::Mode,
            goal: None,
            modes: Vec::new(),
            mode_seen: false,
            airborne_seen: !ctx.tel.flight.on_ground(ctx.tel.armed),
        };
        request_landed_state(ctx);
        match binding {
            FlightBinding::Takeoff { .. } => {
                f.modes = if px4 {
                    // Commander's AUTO.TAKEOFF (main 4, sub 2), then the navigator's loiter.
                    vec![PX4_AUTO_TAKEOFF, modes.hold.custom_mode()]
                } else {
                    vec![modes.guided.custom_mode()]
                };
                if !ctx.tel.armed && ctx.cfg.authority.arm == super::authority::Arming::Operator {
                    return Err(StartError::NotArmed);
                }
                if px4 {
                    f.arm_or_takeoff(ctx, start.id);
                } else {
                    let guided = modes.guided;
                    ctx.set_mode(start.id, guided);
                }
            }
            FlightBinding::FlyTo { to, .. } => {
                let goal = start
                    .arg(to)
                    .and_then(|a| a.as_enu())
                    .ok_or_else(|| StartError::NoLocation(to.clone()))?;
                if ctx.tel.flight.on_ground(ctx.tel.armed) {
                    return Err(StartError::OnGround);
                }
                f.goal = Some(goal);
                f.modes = vec![modes.guided.custom_mode()];
                f.reposition(ctx, start.id);
            }
            FlightBinding::Land { home, .. } => {
                let mode = if *home { Some(modes.rtl) } else { modes.land };
                let Some(mode) = mode else {
                    return Err(StartError::NoLandMode);
                };
                f.goal = home.then(Enu::default);
                f.modes = vec![mode.custom_mode()];
                ctx.set_mode(start.id, mode);
            }
        }
        Ok(f)
    }

    /// ARM when disarmed (the companion arms), else the takeoff.
    fn arm_or_takeoff(&mut self, ctx: &mut Ctx, id: u64) {
        if ctx.tel.armed {
            self.takeoff(ctx, id);
        } else {
            ctx.arm(id);
            self.phase = Phase::Arming;
        }
    }

    fn takeoff(&mut self, ctx: &mut Ctx, id: u64) {
        let FlightBinding::Takeoff { altitude_m, .. } = self.binding else {
            return;
        };
        // ArduCopter: metres above home (frame implied by COMMAND_LONG); PX4: AMSL, NaN lets it use
        // MIS_TAKEOFF_ALT when home's altitude is not known yet.
        let alt = match ctx.cfg.autopilot {
            Autopilot::Ardupilot => altitude_m as f32,
            Autopilot::Px4 => ctx
                .tel
                .flight
                .home_amsl()
                .map_or(f32::NAN, |h| (h + altitude_m) as f32),
        };
        let cmd = Command::long(
            MavCmd::MAV_CMD_NAV_TAKEOFF,
            ctx.target,
            [0.0, 0.0, 0.0, f32::NAN, f32::NAN, f32::NAN, alt],
        );
        ctx.command(id, cmd);
        self.phase = Phase::Starting;
    }

    fn reposition(&mut self, ctx: &mut Ctx, id: u64) {
        let (FlightBinding::FlyTo { speed_m_s, .. }, Some(goal)) = (&self.binding, self.goal)
        else {
            return;
        };
        let (lat, lon, _) = ctx.cfg.home.to_global(goal);
        let (frame, z, speed) = match ctx.cfg.autopilot {
            // Above home: no dependence on the configuration's home altitude. ArduCopter reads frames 3
            // and 6 alike (`mavlink_coordinate_frame_to_location_alt_frame`).
            Autopilot::Ardupilot => (
                MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
                goal.up as f32,
                -1.0,
            ),
            // PX4 compares the frame with MAV_FRAME_GLOBAL_INT (5) itself: its successor (0) is refused.
            #[allow(deprecated)]
            Autopilot::Px4 => (
                MavFrame::MAV_FRAME_GLOBAL_INT,
                ctx.tel
                    .flight
                    .home_amsl()
                    .map_or(f32::NAN, |h| (h + goal.up) as f32),
                *speed_m_s as f32,
            ),
        };
        // param2 = MAV_DO_REPOSITION_FLAGS_CHANGE_MODE.
        let cmd = Command::Int(COMMAND_INT_DATA {
            param1: speed,
            param2: 1.0,
            param3: 0.0,
            param4: f32::NAN,
            x: deg_to_e7(lat),
            y: deg_to_e7(lon),
            z,
            command: MavCmd::MAV_CMD_DO_REPOSITION,
            target_system: ctx.target.0,
            target_component: ctx.target.1,
            frame,
            current: 0,
            autocontinue: 0,
        });
        ctx.command(id, cmd);
        self.phase = Phase::Starting;
    }

    /// ArduCopter takes a speed in GUIDED by DO_CHANGE_SPEED (ground speed), after the reposition.
    fn speed_after_ack(&self, ctx: &mut Ctx, id: u64) {
        if let FlightBinding::FlyTo { speed_m_s, .. } = self.binding {
            super::actions::change_speed(ctx, id, speed_m_s);
        }
    }

    pub fn on_command(
        &mut self,
        ctx: &mut Ctx,
        id: u64,
        cmd: MavCmd,
        outcome: CommandOutcome,
    ) -> Option<FlightEnd> {
        if cmd == MavCmd::MAV_CMD_DO_CHANGE_SPEED {
            if outcome != CommandOutcome::Accepted {
                tracing::warn!(
                    id,
                    ?outcome,
                    "the flight's speed was not taken: the autopilot's own"
                );
            }
            return None;
        }
        match outcome {
            CommandOutcome::Rejected(r) => {
                return Some(FlightEnd::Failed(format!(
                    "{cmd:?} refused: {}",
                    super::actions::result_name(r)
                )))
            }
            CommandOutcome::TimedOut { tries } => {
                let done = match cmd {
                    MavCmd::MAV_CMD_COMPONENT_ARM_DISARM => ctx.tel.armed,
                    MavCmd::MAV_CMD_DO_SET_MODE | MavCmd::MAV_CMD_DO_REPOSITION => {
                        ctx.tel.custom_mode.is_some_and(|m| self.modes.contains(&m))
                    }
                    _ => false,
                };
                if !done {
                    return Some(FlightEnd::Failed(format!(
                        "no COMMAND_ACK for {cmd:?} after {tries} tries"
                    )));
                }
            }
            CommandOutcome::Accepted => {}
        }
        match (self.phase, &self.binding) {
            (Phase::Mode, FlightBinding::Takeoff { .. }) => self.arm_or_takeoff(ctx, id),
            (Phase::Arming, FlightBinding::Takeoff { .. }) => self.takeoff(ctx, id),
            (Phase::Starting, _) => {
                self.phase = Phase::Running;
                self.speed_after_ack(ctx, id);
            }
            (Phase::Mode, FlightBinding::Land { .. }) => self.phase = Phase::Running,
            _ => {}
        }
        None
    }

    pub fn on_message(&mut self, ctx: &mut Ctx, msg: &MavMessage) -> Option<FlightEnd> {
        let MavMessage::HEARTBEAT(h) = msg else {
            return None;
        };
        let armed = h
            .base_mode
            .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED);
        let landing = matches!(self.binding, FlightBinding::Land { .. });
        if landing && !armed && self.mode_seen && self.airborne_seen {
            // Disarmed by its landing: over, whatever mode follows (PX4 switches back to the mode before
            // AUTO.LAND / AUTO.RTL at the disarm, UserModeIntention::onDisarm).
            return Some(self.landed(ctx));
        }
        if self.modes.contains(&h.custom_mode) {
            self.mode_seen = true;
        } else if self.mode_seen {
            return Some(FlightEnd::Failed(format!(
                "foreign mode change to {}",
                super::mode_names::mode_name(h.custom_mode, Some(h.mavtype))
            )));
        }
        // A landing disarms the vehicle (ArduCopter's ModeLand, RTL); anything else disarmed in the air
        // has lost its flight.
        if !armed && self.mode_seen && self.airborne_seen && !landing {
            return Some(FlightEnd::Failed("the vehicle disarmed".into()));
        }
        None
    }

    pub fn on_tick(&mut self, ctx: &mut Ctx) -> Option<FlightEnd> {
        let fl = &ctx.tel.flight;
        let on_ground = fl.on_ground(ctx.tel.armed);
        if !on_ground {
            self.airborne_seen = true;
        }
        if self.phase != Phase::Running {
            return None;
        }
        match &self.binding {
            FlightBinding::Takeoff {
                altitude_m,
                vertical_acceptance_m,
            } => {
                let alt = fl.relative_alt_m?;
                ((alt - altitude_m).abs() <= *vertical_acceptance_m && !on_ground)
                    .then_some(FlightEnd::Nominal)
            }
            FlightBinding::FlyTo {
                acceptance_radius_m,
                vertical_acceptance_m,
                ..
            } => {
                let (p, g, alt) = (ctx.tel.position?, self.goal?, fl.relative_alt_m?);
                (p.horizontal_distance(&g) <= *acceptance_radius_m
                    && (alt - g.up).abs() <= *vertical_acceptance_m)
                    .then_some(FlightEnd::Nominal)
            }
            FlightBinding::Land { .. } => {
                (on_ground && self.airborne_seen && self.mode_seen).then(|| self.landed(ctx))
            }
        }
    }

    /// A landing over: nominal where it was to land (home for a return), else failed with how far off.
    fn landed(&self, ctx: &Ctx) -> FlightEnd {
        let FlightBinding::Land {
            acceptance_radius_m,
            ..
        } = self.binding
        else {
            return FlightEnd::Nominal;
        };
        let off = match (self.goal, ctx.tel.position) {
            (Some(g), Some(p)) => p.horizontal_distance(&g),
            _ => 0.0,
        };
        if off <= acceptance_radius_m {
            FlightEnd::Nominal
        } else {
            FlightEnd::Failed(format!("landed {off:.1} m from home"))
        }
    }

    /// The autopilot restarted under the run: a copter that restarts has fallen; nothing is resumed.
    pub fn resume(&mut self) -> FlightEnd {
        FlightEnd::Failed("the autopilot restarted in flight".into())
    }
}

/// SET_MESSAGE_INTERVAL for EXTENDED_SYS_STATE (fire and forget).
fn request_landed_state(ctx: &mut Ctx) {
    let cmd = Command::long(
        MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
        ctx.target,
        [
            EXTENDED_SYS_STATE_ID,
            EXTENDED_SYS_STATE_US,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
        ],
    );
    ctx.cmds.send(u64::MAX, cmd, ctx.now, ctx.out);
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::ardupilotmega::{MavVtolState, EXTENDED_SYS_STATE_DATA};

    #[test]
    fn a_land_binding_needs_a_landing_mode_and_a_takeoff_an_altitude() {
        let mut modes = crate::config::tests::rover_modes();
        let land = FlightBinding::Land {
            home: false,
            acceptance_radius_m: 2.0,
            position_variable: "position".into(),
        };
        assert_eq!(land.invalid(&modes).map(|(k, _)| k), Some("kind"));
        modes.land = Some(crate::config::Mode::Number(9));
        assert_eq!(land.invalid(&modes), None);
        let takeoff = FlightBinding::Takeoff {
            altitude_m: 0.0,
            vertical_acceptance_m: 1.0,
        };
        assert_eq!(takeoff.invalid(&modes).map(|(k, _)| k), Some("altitude_m"));
    }

    #[test]
    fn the_landed_state_wins_over_the_altitude() {
        // No EXTENDED_SYS_STATE: disarmed near home's altitude is on the ground, armed is not.
        let mut t = FlightTelemetry {
            relative_alt_m: Some(0.2),
            ..Default::default()
        };
        assert!(t.on_ground(false));
        assert!(!t.on_ground(true));
        t.update(&MavMessage::EXTENDED_SYS_STATE(EXTENDED_SYS_STATE_DATA {
            vtol_state: MavVtolState::MAV_VTOL_STATE_UNDEFINED,
            landed_state: MavLandedState::MAV_LANDED_STATE_LANDING,
        }));
        assert!(!t.on_ground(false));
    }

    #[test]
    fn the_battery_reservoir_is_the_charge_above_the_reserve() {
        let names = crate::config::ResourceNames {
            battery: Some("BATTERY".into()),
            battery_reserve: Some(25.0),
            ..Default::default()
        };
        assert_eq!(names.battery_level(57.0), 32.0);
        assert_eq!(names.battery_level(20.0), -5.0);
    }
}
