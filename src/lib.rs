//! mavtempo: IxTeT-eXeC style temporal planning, execution and plan repair for MAVLink vehicles.
//!
//! The layers are crates, each depending only on those below it:
//! - `mavtempo-temporal` (src/temporal): `lang` / `pddl` → `model` → `planner` over `plan` and `stn`; the
//!   independent plan checker `plan::validate`;
//! - `mavtempo-vehicle` (src/vehicle): the [`vehicle::Vehicle`] interface, its mock and its MAVLink
//!   implementation, configuration and goal intake;
//! - `mavtempo-executive` (src/executive): the executive (`exec`) and the dispatch policies (`dispatch`);
//! - this package, the application: the command line (`cli`), the pictures of a run (`report`), the
//!   benchmarks (`bench`), the dispatch experiment (`experiment`), the fuzz targets (`fuzz`) and the stepped
//!   SITL (`sitl_pacer`). It names the layers' modules at its root, so a user writes `mavtempo::model`.

pub use mavtempo_executive::{config_check, dispatch, exec, mapping};
pub use mavtempo_temporal::{lang, model, pddl, plan, planner, stn};
pub use mavtempo_vehicle as vehicle;

pub mod bench;
pub mod cli;
pub mod experiment;
pub mod fuzz;
pub mod report;
pub mod sitl_pacer;
