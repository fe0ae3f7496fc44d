//! planner (see DESIGN in README).
