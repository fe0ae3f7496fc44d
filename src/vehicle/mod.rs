//! vehicle (see DESIGN in README).
