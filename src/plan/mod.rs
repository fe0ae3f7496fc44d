//! plan (see DESIGN in README).
