//! model (see DESIGN in README).
