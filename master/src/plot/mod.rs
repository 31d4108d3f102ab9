//! Plots of a run-up as SVG (and PNG).
