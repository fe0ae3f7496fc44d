//! lang (see DESIGN in README).
