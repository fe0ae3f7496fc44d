//! stn (see DESIGN in README).
