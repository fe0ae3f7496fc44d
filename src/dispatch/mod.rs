//! dispatch (see DESIGN in README).
