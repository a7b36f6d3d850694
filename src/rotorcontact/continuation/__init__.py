"""Continuation: the pseudo-arclength engine, branches of periodic orbits with their typed events,
zero curves of F1 and two-parameter curves (codim-2)."""
