"""Analyses of the model: equilibria and their boundary-equilibrium bifurcations, the local analysis
of the non-smooth fold-Hopf, and Lyapunov exponents with saltation corrections."""
