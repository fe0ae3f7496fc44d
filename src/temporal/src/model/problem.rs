//! A problem: objects, the initial scenario Φ_0 (initial values and predicted exogenous changes), resource
//! levels and availability profiles, a horizon and goals.

use std::collections::HashMap;
use std::sync::Arc;

use serde::Serialize;

use super::ids::append_named;
use super::{
    AttrId, Domain, GeoPoint, Goal, GoalId, Object, ObjectId, ResourceId, Time, TypeId, Value,
};

/// A ground value of an attribute instance: `attr(args) = value`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize)]
pub struct Fact {
    pub attr: AttrId,
    pub args: Vec<ObjectId>,
    pub value: Value,
}

/// A predicted exogenous change (part of Φ_0): from `at` on, the attribute instance takes `fact.value`,
/// independently of the plan (e.g. visibility windows W1/W2 of a ground station).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize)]
pub struct TimedFact {
    pub at: Time,
    pub fact: Fact,
}

/// An `initial` statement with `*` arguments (`PICTURE(*) = false;`): `None` marks a wildcard. Kept so that
/// objects added at run time (a location reported by the vehicle or named by a ground station) get the
/// same initial values as the problem's own objects.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize)]
pub struct DefaultFact {
    pub at: Time,
    pub attr: AttrId,
    pub args: Vec<Option<ObjectId>>,
    pub value: Value,
}

/// Initial level and expected availability profile of one resource.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResourceSetup {
    /// The level at the origin (a reservoir's content; unary resources: 1 = free).
    pub level: f64,
    /// Piecewise-constant capacity: `(from, capacity)` steps sorted by time, the first at 0.
    pub profile: Vec<(Time, f64)>,
}

impl ResourceSetup {
    /// The expected capacity at time `t` (the last step at or before `t`).
    pub fn capacity_at(&self, t: Time) -> f64 {
        self.profile
            .iter()
            .take_while(|(from, _)| *from <= t)
            .last()
            .or(self.profile.first())
            .map_or(0.0, |&(_, c)| c)
    }
}

/// A planning problem over a [`Domain`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Problem {
    pub name: String,
    /// The domain's name (`domain rover;`).
    pub domain: String,
    /// Clock time of the origin since midnight (`start 08:00;`), used to print and read clock times.
    pub start_clock: Option<Time>,
    /// The geographic home that local coordinates are relative to.
    pub home: Option<GeoPoint>,
    /// End of the mission, relative to the origin.
    pub horizon: Time,
    /// All objects: the domain's constants first (same ids), then the problem's objects.
    pub objects: Vec<Object>,
    /// Initial values at the origin (ground, one per attribute instance; unlisted instances are `+oo`).
    pub initial: Vec<Fact>,
    /// Predicted exogenous changes after the origin, sorted by time.
    pub exogenous: Vec<TimedFact>,
    /// One setup per domain resource, indexed by [`ResourceId`].
    pub resources: Vec<ResourceSetup>,
    /// Φ_g = Φ_ge ∪ Φ_gi, indexed by [`GoalId`].
    pub goals: Vec<Goal>,
    /// The wildcard statements of `initial`, already expanded into `initial` / `exogenous`.
    pub defaults: Vec<DefaultFact>,
    /// Where the vehicle may drive (its range, a fence): a straight leg between two places that leaves
    /// them has no distance, so no action whose duration depends on it can be inserted.
    #[serde(skip)]
    pub legs: Legs,
    #[serde(skip)]
    object_index: HashMap<String, ObjectId>,
}

/// Which straight legs between two places a vehicle may drive (a range from home, a fence: the vehicle
/// layer's limits, handed over by the executive).
pub trait LegLimits: Send + Sync + std::fmt::Debug {
    /// Whether the straight leg from `a` to `b` (metres east, north of the problem's home) stays within.
    fn allows(&self, a: (f64, f64), b: (f64, f64)) -> bool;
}

/// A problem's [`LegLimits`], none by default; two are equal when they are the same limits.
#[derive(Clone, Debug, Default)]
pub struct Legs(pub Option<Arc<dyn LegLimits>>);

impl PartialEq for Legs {
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

impl Problem {
    /// An empty problem over `domain`: its constants, default resource setups (full, domain capacity),
    /// horizon `horizon`.
    pub fn new(name: impl Into<String>, domain: &Domain, horizon: Time) -> Self {
        let resources = domain
            .resources
            .iter()
            .map(|r| ResourceSetup {
                level: r.capacity,
                profile: vec![(0, r.capacity)],
            })
            .collect();
        let mut p = Problem {
            name: name.into(),
            domain: domain.name.clone(),
            start_clock: None,
            home: None,
            horizon,
            objects: Vec::new(),
            initial: Vec::new(),
            exogenous: Vec::new(),
            resources,
            goals: Vec::new(),
            defaults: Vec::new(),
            legs: Legs::default(),
            object_index: HashMap::new(),
        };
        for o in &domain.objects {
            p.add_object(o.clone());
        }
        p
    }

    /// Appends an object (a problem object, or a location discovered at run time) and returns its id.
    pub fn add_object(&mut self, object: Object) -> ObjectId {
        append_named(
            &mut self.objects,
            &mut self.object_index,
            object.name.clone(),
            object,
        )
    }

    /// Appends an object and the facts the problem's wildcard `initial` statements give it (e.g. a new
    /// location gets `PICTURE(new) = false`); returns its id.
    pub fn add_object_with_defaults(&mut self, d: &Domain, object: Object) -> ObjectId {
        self.add_object_like(d, object, None)
    }

    /// [`Self::add_object_with_defaults`], where the new object's facts on the attributes of `like.1` are
    /// those of the object `like.0` instead of the defaults (a place met on the way from `like.0` keeps its
    /// static relations, e.g. its routes).
    pub fn add_object_like(
        &mut self,
        d: &Domain,
        object: Object,
        like: Option<(ObjectId, &[AttrId])>,
    ) -> ObjectId {
        let id = self.add_object(object);
        let mut new_facts: Vec<(Time, Fact)> = Vec::new();
        for def in &self.defaults {
            let Some(attr) = d.attrs.get(def.attr.index()) else {
                continue;
            };
            // Every instance of the pattern that involves the new object at a wildcard position.
            let mut combos: Vec<(Vec<ObjectId>, bool)> = vec![(Vec::new(), false)];
            for (arg, (_, pty)) in def.args.iter().zip(&attr.params) {
                let choices = match arg {
                    Some(o) => vec![*o],
                    None => self.objects_of(*pty),
                };
                combos = combos
                    .into_iter()
                    .flat_map(|(c, hit)| {
                        choices.iter().map(move |o| {
                            let mut c = c.clone();
                            c.push(*o);
                            (c, hit || (*o == id && arg.is_none()))
                        })
                    })
                    .collect();
            }
            for (args, hit) in combos {
                if hit {
                    new_facts.push((
                        def.at,
                        Fact {
                            attr: def.attr,
                            args,
                            value: def.value,
                        },
                    ));
                }
            }
        }
        if let Some((model, attrs)) = like {
            for (_, f) in new_facts
                .iter_mut()
                .filter(|(_, f)| attrs.contains(&f.attr))
            {
                let args: Vec<ObjectId> = f
                    .args
                    .iter()
                    .map(|&o| if o == id { model } else { o })
                    .collect();
                // The last fact on the instance is the one in force (a wildcard comes first).
                if let Some(m) = self
                    .initial
                    .iter()
                    .rev()
                    .find(|g| g.attr == f.attr && g.args == args)
                {
                    f.value = m.value;
                }
            }
        }
        self.add_facts(new_facts);
        id
    }

    /// Adds facts to the initial scenario: at the origin into `initial`, later ones into `exogenous`
    /// (kept sorted by time).
    pub fn add_facts(&mut self, facts: impl IntoIterator<Item = (Time, Fact)>) {
        for (at, fact) in facts {
            if at == 0 {
                self.initial.push(fact);
            } else {
                self.exogenous.push(TimedFact { at, fact });
            }
        }
        self.exogenous.sort_by_key(|f| f.at);
    }

    /// The object named `name` (domain constants included).
    pub fn object_id(&self, name: &str) -> Option<ObjectId> {
        self.object_index.get(name).copied()
    }

    /// The object `id`.
    pub fn object(&self, id: ObjectId) -> Option<&Object> {
        self.objects.get(id.index())
    }

    /// The name of `id`, or `?` for an unknown id (printing helper).
    pub fn object_name(&self, id: ObjectId) -> &str {
        self.object(id).map_or("?", |o| o.name.as_str())
    }

    /// All objects of type `ty`, in declaration order.
    pub fn objects_of(&self, ty: TypeId) -> Vec<ObjectId> {
        (0..self.objects.len())
            .map(ObjectId::from_index)
            .filter(|&o| self.objects[o.index()].ty == ty)
            .collect()
    }

    /// The goal named `name`.
    pub fn goal_id(&self, name: &str) -> Option<GoalId> {
        self.goals
            .iter()
            .position(|g| g.name == name)
            .map(GoalId::from_index)
    }

    /// The initial value of `attr(args)` (`+oo` if not given).
    pub fn initial_value(&self, attr: AttrId, args: &[ObjectId]) -> Value {
        self.initial
            .iter()
            .find(|f| f.attr == attr && f.args == args)
            .map_or(Value::Unknown, |f| f.value)
    }

    /// Straight-line metres between two objects with positions (`None` if either has none).
    pub fn distance(&self, a: ObjectId, b: ObjectId) -> Option<f64> {
        let pa = self.object(a)?.position?;
        let pb = self.object(b)?.position?;
        Some(pa.distance(&pb, self.home.as_ref()))
    }

    /// Whether the vehicle may drive the straight leg between two objects ([`Self::legs`]); true when either
    /// has no position or no limits are set.
    pub fn leg_allowed(&self, a: ObjectId, b: ObjectId) -> bool {
        let Some(limits) = &self.legs.0 else {
            return true;
        };
        let (Some(pa), Some(pb)) = (
            self.object(a).and_then(|o| o.position),
            self.object(b).and_then(|o| o.position),
        ) else {
            return true;
        };
        let (ea, na, _) = pa.to_local(self.home.as_ref());
        let (eb, nb, _) = pb.to_local(self.home.as_ref());
        limits.allows((ea, na), (eb, nb))
    }

    /// The resource setup of `r`.
    pub fn resource(&self, r: ResourceId) -> Option<&ResourceSetup> {
        self.resources.get(r.index())
    }
}

/// Every way to take one object from each of `choices` in turn (the ground instances of an attribute or a
/// predicate whose arguments may take these objects), in lexicographic order.
pub fn combinations(choices: &[Vec<ObjectId>]) -> Vec<Vec<ObjectId>> {
    let mut out: Vec<Vec<ObjectId>> = vec![Vec::new()];
    for c in choices {
        out = out
            .into_iter()
            .flat_map(|prefix| {
                c.iter().map(move |o| {
                    let mut v = prefix.clone();
                    v.push(*o);
                    v
                })
            })
            .collect();
    }
    out
}
