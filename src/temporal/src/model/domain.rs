//! A domain: types, domain-level constants, attributes, resources and tasks, with name lookups.

use std::collections::HashMap;

use serde::Serialize;

use super::ids::append_named;
use super::{
    AttrId, LogicalAttr, Object, ObjectId, ResourceAttr, ResourceId, Task, TaskId, Type, TypeId,
    TypeKind,
};

/// Everything a domain file declares. Tables are indexed by the id newtypes; the maps give name → id.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Domain {
    pub name: String,
    /// The file it was read from, as given to the loader (`domains/auv/auv.ixt`), so that messages about
    /// its declarations can say `file:line`; `None` when built in code.
    pub source: Option<String>,
    /// `types[0]` is the builtin `bool`.
    pub types: Vec<Type>,
    /// Domain-level constants: `false`, `true` (ids 0 and 1), enumeration members, then `constant`s.
    /// A problem's object table starts with exactly these, under the same ids.
    pub objects: Vec<Object>,
    pub attrs: Vec<LogicalAttr>,
    pub resources: Vec<ResourceAttr>,
    pub tasks: Vec<Task>,
    #[serde(skip)]
    names: Names,
}

/// Name → id of each of the domain's tables, filled as the tables are.
#[derive(Debug, Clone, Default, PartialEq)]
struct Names {
    types: HashMap<String, TypeId>,
    objects: HashMap<String, ObjectId>,
    attrs: HashMap<String, AttrId>,
    resources: HashMap<String, ResourceId>,
    tasks: HashMap<String, TaskId>,
}

impl Domain {
    /// The builtin boolean type.
    pub const BOOL: TypeId = TypeId(0);
    /// The builtin constant `false`.
    pub const FALSE: ObjectId = ObjectId(0);
    /// The builtin constant `true`.
    pub const TRUE: ObjectId = ObjectId(1);

    /// The builtin constant `true` or `false`.
    pub fn truth(b: bool) -> ObjectId {
        if b {
            Self::TRUE
        } else {
            Self::FALSE
        }
    }

    /// An empty domain holding only `bool`, `false` and `true`.
    pub fn new(name: impl Into<String>) -> Self {
        let mut d = Domain {
            name: name.into(),
            source: None,
            types: Vec::new(),
            objects: Vec::new(),
            attrs: Vec::new(),
            resources: Vec::new(),
            tasks: Vec::new(),
            names: Names::default(),
        };
        let b = d.add_type("bool", TypeKind::Enum);
        d.add_enum_member(b, "false");
        d.add_enum_member(b, "true");
        d
    }

    /// Adds a type and returns its id (the caller checks the name is fresh).
    pub fn add_type(&mut self, name: &str, kind: TypeKind) -> TypeId {
        let ty = Type {
            name: name.to_string(),
            kind,
            members: Vec::new(),
            line: None,
        };
        append_named(&mut self.types, &mut self.names.types, name.to_string(), ty)
    }

    /// Adds a constant of enumeration `ty` (also usable for domain-level constants of object types).
    pub fn add_enum_member(&mut self, ty: TypeId, name: &str) -> ObjectId {
        let id = self.add_object(Object {
            name: name.to_string(),
            ty,
            position: None,
        });
        if let Some(t) = self.types.get_mut(ty.index()) {
            t.members.push(id);
        }
        id
    }

    /// Adds a domain-level object and returns its id.
    pub fn add_object(&mut self, object: Object) -> ObjectId {
        append_named(
            &mut self.objects,
            &mut self.names.objects,
            object.name.clone(),
            object,
        )
    }

    /// Adds a logical attribute.
    pub fn add_attr(&mut self, attr: LogicalAttr) -> AttrId {
        append_named(
            &mut self.attrs,
            &mut self.names.attrs,
            attr.name.clone(),
            attr,
        )
    }

    /// Adds a resource attribute.
    pub fn add_resource(&mut self, res: ResourceAttr) -> ResourceId {
        append_named(
            &mut self.resources,
            &mut self.names.resources,
            res.name.clone(),
            res,
        )
    }

    /// Adds a task.
    pub fn add_task(&mut self, task: Task) -> TaskId {
        append_named(
            &mut self.tasks,
            &mut self.names.tasks,
            task.name.clone(),
            task,
        )
    }

    /// The type named `name`.
    pub fn type_id(&self, name: &str) -> Option<TypeId> {
        self.names.types.get(name).copied()
    }

    /// The domain-level constant named `name` (enumeration members, `true`, `false`).
    pub fn object_id(&self, name: &str) -> Option<ObjectId> {
        self.names.objects.get(name).copied()
    }

    /// The logical attribute named `name`.
    pub fn attr_id(&self, name: &str) -> Option<AttrId> {
        self.names.attrs.get(name).copied()
    }

    /// The resource named `name`.
    pub fn resource_id(&self, name: &str) -> Option<ResourceId> {
        self.names.resources.get(name).copied()
    }

    /// The task named `name`.
    pub fn task_id(&self, name: &str) -> Option<TaskId> {
        self.names.tasks.get(name).copied()
    }

    /// The type `id`. Panics on an id from another domain (ids are only made by this domain).
    pub fn ty(&self, id: TypeId) -> &Type {
        &self.types[id.index()]
    }

    /// The attribute `id`.
    pub fn attr(&self, id: AttrId) -> &LogicalAttr {
        &self.attrs[id.index()]
    }

    /// The resource `id`.
    pub fn resource(&self, id: ResourceId) -> &ResourceAttr {
        &self.resources[id.index()]
    }

    /// The task `id`.
    pub fn task(&self, id: TaskId) -> &Task {
        &self.tasks[id.index()]
    }

    /// `file:line` of a declaration at `line` of this domain's file, when both are known.
    pub fn location(&self, line: Option<usize>) -> Option<String> {
        Some(format!("{}:{}", self.source.as_deref()?, line?))
    }

    /// Tasks with a primary event on `attr` (candidate establishers for an open condition on it).
    pub fn tasks_establishing(&self, attr: AttrId) -> Vec<TaskId> {
        (0..self.tasks.len())
            .map(TaskId::from_index)
            // A main attribute is one a primary event changes ([`Task::main_attributes`]), tested without
            // listing them: the planner asks this for every open condition it examines.
            .filter(|&t| {
                self.task(t)
                    .events
                    .iter()
                    .any(|e| e.primary && e.attr == attr)
            })
            .collect()
    }

    /// Tasks producing `res` as a primary effect (candidate resolvers of a reservoir under-flow).
    pub fn tasks_producing(&self, res: ResourceId) -> Vec<TaskId> {
        (0..self.tasks.len())
            .map(TaskId::from_index)
            .filter(|&t| self.task(t).produced_resources().contains(&res))
            .collect()
    }
}
