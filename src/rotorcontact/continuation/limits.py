"""Limits of the continuation layer, readable without loading it (the command line checks its options against them)."""

#: Most period doublings followed from one branch (each doubles the impacts per period).
MAX_DOUBLINGS = 8
