"""The impact map P_I and its periodic orbits: one-impact orbits from the zeros of F1 (MODEL.md §5),
their fixed-point system, and orbits with several impacts per period."""
