//! `mavtempo bench plan`: planning time and steps on the shipped and generated problems.
