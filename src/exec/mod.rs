//! exec (see DESIGN in README).
