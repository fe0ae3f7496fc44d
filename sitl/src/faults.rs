//! Fault triggers (at a time, on an event) and the link's fault state (blackout, loss,
//! duplication, reordering). What each fault does to the vehicle lives in `autopilot::faults`.

use std::collections::HashMap;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::link::PeerId;
use crate::scenario::{EventKind, Fault, FaultSpec};
use crate::time::{later, secs_to_ms};

/// Something that happened in the sim, which faults can be triggered on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimEvent {
    pub kind: EventKind,
    pub value: i64,
    /// Where the vehicle was (east, north metres from home).
    pub at_m: [f64; 2],
}

#[derive(Debug)]
struct Pending {
    spec: FaultSpec,
    seen: u32,
    due_ms: Option<u64>,
    fired: bool,
}

/// The scenario's faults, waiting for their trigger.
#[derive(Debug, Default)]
pub struct FaultEngine {
    pending: Vec<Pending>,
}

impl FaultEngine {
    pub fn new(specs: &[FaultSpec]) -> Self {
        Self {
            pending: specs
                .iter()
                .map(|s| Pending {
                    spec: s.clone(),
                    seen: 0,
                    due_ms: s.when.at_s.map(secs_to_ms),
                    fired: false,
                })
                .collect(),
        }
    }

    pub fn on_event(&mut self, ev: SimEvent, now_ms: u64) {
        for p in self
            .pending
            .iter_mut()
            .filter(|p| !p.fired && p.due_ms.is_none())
        {
            let w = &p.spec.when;
            if w.on != Some(ev.kind)
                || w.value.is_some_and(|v| v != ev.value)
                || !w.is_near(ev.at_m)
                || w.after_s.is_some_and(|a| now_ms < secs_to_ms(a))
            {
                continue;
            }
            p.seen += 1;
            if p.seen == w.occurrence {
                p.due_ms = Some(later(now_ms, w.delay_s));
            }
        }
    }

    /// Faults whose time has come, in scenario order; each fires once.
    pub fn due(&mut self, now_ms: u64) -> Vec<Fault> {
        let mut out = Vec::new();
        for p in self.pending.iter_mut() {
            if !p.fired && p.due_ms.is_some_and(|d| d <= now_ms) {
                p.fired = true;
                out.push(p.spec.fault.clone());
            }
        }
        out
    }
}

/// What to do with one frame on the link.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delivery {
    Drop,
    Once,
    Twice,
    /// Hold it back and send it after the next frame to the same peer.
    Reorder,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Quality {
    loss: f64,
    duplicate: f64,
    reorder: f64,
    until_ms: Option<u64>,
}

#[derive(Debug)]
pub struct LinkFaults {
    /// Outbound fates: the simulator's frames are the same run after run.
    rng: ChaCha8Rng,
    /// Inbound fates, one stream per message id: how many heartbeats a companion sends depends on its wall
    /// clock, and must not change which of its commands get through.
    inbound_seed: u64,
    inbound_rngs: HashMap<u32, ChaCha8Rng>,
    blackout_until_ms: u64,
    quality: Option<Quality>,
    held: HashMap<PeerId, Vec<u8>>,
    pub dropped: u64,
}

impl LinkFaults {
    pub fn new(mut rng: ChaCha8Rng) -> Self {
        Self {
            inbound_seed: rng.gen(),
            inbound_rngs: HashMap::new(),
            rng,
            blackout_until_ms: 0,
            quality: None,
            held: HashMap::new(),
            dropped: 0,
        }
    }

    pub fn blackout(&mut self, now_ms: u64, duration_s: f64) {
        self.blackout_until_ms = later(now_ms, duration_s);
    }

    pub fn set_quality(
        &mut self,
        now_ms: u64,
        loss: f64,
        duplicate: f64,
        reorder: f64,
        d: Option<f64>,
    ) {
        self.quality = Some(Quality {
            loss,
            duplicate,
            reorder,
            until_ms: d.map(|d| later(now_ms, d)),
        });
    }

    pub fn in_blackout(&self, now_ms: u64) -> bool {
        now_ms < self.blackout_until_ms
    }

    fn quality(&mut self, now_ms: u64) -> Option<Quality> {
        if self
            .quality
            .is_some_and(|q| q.until_ms.is_some_and(|u| now_ms >= u))
        {
            self.quality = None;
        }
        self.quality
    }

    /// An incoming frame's fate (message `msg_id`): the radio loses, duplicates and reorders both ways.
    pub fn inbound(&mut self, now_ms: u64, msg_id: u32) -> Delivery {
        let Some(q) = self.usable(now_ms) else {
            return Delivery::Drop;
        };
        let seed = self.inbound_seed ^ u64::from(msg_id).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        let draw: f64 = match q {
            Some(_) => self
                .inbound_rngs
                .entry(msg_id)
                .or_insert_with(|| ChaCha8Rng::seed_from_u64(seed))
                .gen(),
            None => 1.0,
        };
        self.fate(q, draw)
    }

    /// An outgoing frame's fate.
    pub fn outbound(&mut self, now_ms: u64) -> Delivery {
        let Some(q) = self.usable(now_ms) else {
            return Delivery::Drop;
        };
        let draw: f64 = match q {
            Some(_) => self.rng.gen(),
            None => 1.0,
        };
        self.fate(q, draw)
    }

    /// None in a blackout (the frame is dropped), else the link's quality if degraded.
    fn usable(&mut self, now_ms: u64) -> Option<Option<Quality>> {
        if self.in_blackout(now_ms) {
            self.dropped += 1;
            return None;
        }
        Some(self.quality(now_ms))
    }

    fn fate(&mut self, q: Option<Quality>, draw: f64) -> Delivery {
        let Some(q) = q else {
            return Delivery::Once;
        };
        if draw < q.loss {
            self.dropped += 1;
            Delivery::Drop
        } else if draw < q.loss + q.duplicate {
            Delivery::Twice
        } else if draw < q.loss + q.duplicate + q.reorder {
            Delivery::Reorder
        } else {
            Delivery::Once
        }
    }

    /// A reboot: the frames held back for reordering are lost with the radio's buffers.
    pub fn drop_held(&mut self) {
        self.held.clear();
    }

    pub fn hold(&mut self, peer: PeerId, bytes: Vec<u8>) {
        self.held.insert(peer, bytes);
    }

    pub fn take_held(&mut self, peer: PeerId) -> Option<Vec<u8>> {
        self.held.remove(&peer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Trigger;

    fn spec(when: Trigger) -> FaultSpec {
        FaultSpec {
            when,
            fault: Fault::PictureFails { count: 1 },
        }
    }

    #[test]
    fn time_and_event_triggers_fire_once() {
        let mut e = FaultEngine::new(&[
            spec(Trigger {
                at_s: Some(2.0),
                occurrence: 1,
                ..Trigger::default()
            }),
            spec(Trigger {
                on: Some(EventKind::WaypointReached),
                value: Some(3),
                occurrence: 2,
                delay_s: 1.0,
                ..Trigger::default()
            }),
        ]);
        assert!(e.due(1999).is_empty());
        assert_eq!(e.due(2000).len(), 1);
        assert!(e.due(3000).is_empty());
        let ev = SimEvent {
            kind: EventKind::WaypointReached,
            value: 3,
            at_m: [0.0, 0.0],
        };
        e.on_event(
            SimEvent {
                kind: EventKind::WaypointReached,
                value: 2,
                at_m: [0.0, 0.0],
            },
            4000,
        );
        e.on_event(ev, 5000);
        assert!(e.due(10_000).is_empty());
        e.on_event(ev, 6000);
        assert!(e.due(6999).is_empty());
        assert_eq!(e.due(7000).len(), 1);
    }

    #[test]
    fn a_trigger_near_a_place_fires_only_there() {
        // "The camera hangs on the picture of p2", whichever capture that is.
        let mut e = FaultEngine::new(&[spec(Trigger {
            on: Some(EventKind::PictureStarted),
            near_m: Some([25.0, -10.0]),
            occurrence: 1,
            ..Trigger::default()
        })]);
        let pic = |at_m| SimEvent {
            kind: EventKind::PictureStarted,
            value: 0,
            at_m,
        };
        e.on_event(pic([34.0, 0.0]), 1000);
        e.on_event(pic([10.0, 4.0]), 2000);
        assert!(e.due(10_000).is_empty());
        e.on_event(pic([25.5, -9.0]), 11_000);
        assert_eq!(e.due(11_000).len(), 1);
    }

    #[test]
    fn a_trigger_after_a_time_counts_only_later_events() {
        // "A battery drop during a move late in the mission", whichever move that is.
        let mut e = FaultEngine::new(&[spec(Trigger {
            on: Some(EventKind::Moving),
            after_s: Some(450.0),
            occurrence: 1,
            ..Trigger::default()
        })]);
        let moving = SimEvent {
            kind: EventKind::Moving,
            value: 0,
            at_m: [0.0, 0.0],
        };
        e.on_event(moving, 100_000);
        e.on_event(moving, 449_999);
        assert!(e.due(500_000).is_empty());
        e.on_event(moving, 450_000);
        assert_eq!(e.due(450_000).len(), 1);
    }

    #[test]
    fn loss_rate_is_respected_and_seeded() {
        let run = || {
            let mut l = LinkFaults::new(ChaCha8Rng::seed_from_u64(1));
            l.set_quality(0, 0.3, 0.1, 0.1, None);
            (0..10_000).map(|_| l.outbound(0)).collect::<Vec<_>>()
        };
        let a = run();
        assert_eq!(a, run());
        let drops = a.iter().filter(|d| **d == Delivery::Drop).count();
        assert!((2700..3300).contains(&drops), "{drops}");
        let dups = a.iter().filter(|d| **d == Delivery::Twice).count();
        assert!((800..1200).contains(&dups), "{dups}");
    }

    #[test]
    fn blackout_drops_everything_until_it_ends() {
        let mut l = LinkFaults::new(ChaCha8Rng::seed_from_u64(1));
        l.blackout(1000, 2.0);
        assert_eq!(l.outbound(2999), Delivery::Drop);
        assert_eq!(l.inbound(2000, 0), Delivery::Drop);
        assert_eq!(l.outbound(3000), Delivery::Once);
    }
}
