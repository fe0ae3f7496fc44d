//! The goals each ground station holds on the companion, as the mission protocol sees them: the list a
//! station uploaded (what MISSION_REQUEST_LIST reads back, only goals neither achieved, rejected nor
//! cancelled), replaced by the next list that station uploads (a goal left out of it is cancelled; a goal
//! uploaded again, same items, is kept, not inserted twice).

use std::collections::BTreeMap;

use super::item_goals::GoalList;
use super::items::MissionItem;
use super::types::GoalRequest;

/// A ground station: its MAVLink system and component.
pub type Station = (u8, u8);

/// One goal a station holds and the items it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct HeldGoal {
    pub request: GoalRequest,
    pub items: Vec<MissionItem>,
    pub ordinal: usize,
}

impl HeldGoal {
    fn same(&self, items: &[MissionItem], ordinal: usize) -> bool {
        self.ordinal == ordinal && self.items == items
    }
}

/// A new list from a station against what it holds.
#[derive(Debug, Clone, Default)]
pub struct Replacement {
    /// Goals to request (new in the list).
    pub new: Vec<HeldGoal>,
    /// Goals held and uploaded again: kept as they are.
    pub kept: Vec<HeldGoal>,
    /// Goals held and left out of the list: to cancel.
    pub dropped: Vec<String>,
}

/// Why a goal cannot be withdrawn on its own.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WithdrawError {
    #[error(
        "{0} is not held by a ground station (achieved, rejected, cancelled, or from the problem)"
    )]
    NotHeld(String),
    #[error("{goal} was made from the same mission items as {with}: withdraw both (upload the list without them)")]
    SharedItems { goal: String, with: String },
}

#[derive(Debug, Default)]
pub struct HeldGoals {
    by_station: BTreeMap<Station, Vec<HeldGoal>>,
}

impl HeldGoals {
    /// What `list` (mapped from `items`) changes for `station`.
    pub fn replace(&self, station: Station, items: &[MissionItem], list: &GoalList) -> Replacement {
        let held = self.by_station.get(&station).map_or(&[][..], Vec::as_slice);
        let mut r = Replacement::default();
        let mut matched = vec![false; held.len()];
        for g in &list.goals {
            let its = items.get(g.items.clone()).unwrap_or(&[]).to_vec();
            let found = held
                .iter()
                .enumerate()
                .find(|(k, h)| !matched[*k] && h.same(&its, g.ordinal));
            match found {
                Some((k, h)) => {
                    matched[k] = true;
                    r.kept.push(h.clone());
                }
                None => r.new.push(HeldGoal {
                    request: g.request.clone(),
                    items: its,
                    ordinal: g.ordinal,
                }),
            }
        }
        r.dropped = held
            .iter()
            .zip(&matched)
            .filter(|(_, m)| !**m)
            .map(|(h, _)| h.request.name.clone())
            .collect();
        r
    }

    /// `station` now holds `goals`.
    pub fn set(&mut self, station: Station, goals: Vec<HeldGoal>) {
        if goals.is_empty() {
            self.by_station.remove(&station);
        } else {
            self.by_station.insert(station, goals);
        }
    }

    /// The names `station` holds.
    pub fn names(&self, station: Station) -> Vec<String> {
        self.by_station
            .get(&station)
            .map(|v| v.iter().map(|h| h.request.name.clone()).collect())
            .unwrap_or_default()
    }

    /// Every goal held, with the station that holds it.
    pub fn holders(&self) -> Vec<(String, Station)> {
        self.by_station
            .iter()
            .flat_map(|(s, v)| v.iter().map(move |h| (h.request.name.clone(), *s)))
            .collect()
    }

    /// The list the station holding `name` would upload to withdraw it (the mission protocol's list
    /// replacement: a goal left out is cancelled), and that station.
    pub fn list_without(&self, name: &str) -> Result<(Station, Vec<MissionItem>), WithdrawError> {
        let (station, goals) = self
            .by_station
            .iter()
            .find(|(_, v)| v.iter().any(|h| h.request.name == name))
            .ok_or_else(|| WithdrawError::NotHeld(name.to_string()))?;
        let Some(goal) = goals.iter().find(|h| h.request.name == name) else {
            return Err(WithdrawError::NotHeld(name.to_string()));
        };
        // Goals made from the same items (the pictures of one trigger distance) leave together or not at all.
        if let Some(twin) = goals
            .iter()
            .find(|h| h.request.name != name && h.items == goal.items)
        {
            return Err(WithdrawError::SharedItems {
                goal: name.to_string(),
                with: twin.request.name.clone(),
            });
        }
        let mut out: Vec<MissionItem> = Vec::new();
        let mut last: Option<&[MissionItem]> = None;
        for h in goals.iter().filter(|h| h.request.name != name) {
            if last != Some(h.items.as_slice()) {
                out.extend(h.items.iter().cloned());
            }
            last = Some(&h.items);
        }
        Ok((*station, out))
    }

    /// Goal `name` is no longer held (achieved, rejected, cancelled).
    pub fn release(&mut self, name: &str) {
        for v in self.by_station.values_mut() {
            v.retain(|h| h.request.name != name);
        }
        self.by_station.retain(|_, v| !v.is_empty());
    }

    /// The items `station` holds, in upload order, each item once (the pictures of one trigger distance
    /// share their items).
    pub fn items(&self, station: Station) -> Vec<MissionItem> {
        let mut out: Vec<MissionItem> = Vec::new();
        let mut last: Option<&[MissionItem]> = None;
        for h in self.by_station.get(&station).map_or(&[][..], Vec::as_slice) {
            if last != Some(h.items.as_slice()) {
                out.extend(h.items.iter().cloned());
            }
            last = Some(&h.items);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::GoalKind;
    use mavlink::dialects::ardupilotmega::{MavCmd, MavFrame};

    fn held(name: &str, x: f64, ordinal: usize) -> HeldGoal {
        let mut item = MissionItem::new(MavCmd::MAV_CMD_NAV_WAYPOINT, MavFrame::MAV_FRAME_GLOBAL);
        item.x = x;
        HeldGoal {
            request: GoalRequest {
                name: name.into(),
                kind: GoalKind::BeAt,
                proposition: format!("at({name}_loc)"),
                location: None,
                priority: 1,
                start_window_s: (0.0, 100.0),
                duration_s: (0.0, 0.0),
                d_achiev_s: 0.0,
            },
            items: vec![item],
            ordinal,
        }
    }

    #[test]
    fn a_goal_is_withdrawn_by_its_stations_list_without_it() {
        let mut h = HeldGoals::default();
        h.set((255, 190), vec![held("g6", 1.0, 0), held("g7", 2.0, 0)]);
        h.set((255, 230), vec![held("g8", 3.0, 0)]);
        let (station, items) = h.list_without("g6").expect("held");
        assert_eq!(station, (255, 190));
        assert_eq!(items.iter().map(|i| i.x).collect::<Vec<_>>(), [2.0]);
        let (station, items) = h.list_without("g8").expect("held");
        assert_eq!((station, items.len()), ((255, 230), 0));
        assert_eq!(
            h.list_without("g1"),
            Err(WithdrawError::NotHeld("g1".into()))
        );
        // Two pictures of one trigger distance share their items: not one without the other.
        h.set((1, 1), vec![held("g9", 4.0, 0), held("g10", 4.0, 1)]);
        assert!(matches!(
            h.list_without("g9"),
            Err(WithdrawError::SharedItems { .. })
        ));
        let mut holders = h.holders();
        holders.sort();
        assert_eq!(holders.len(), 5);
        assert!(holders.contains(&("g7".to_string(), (255, 190))));
    }
}
