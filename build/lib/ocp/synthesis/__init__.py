"""The optimal synthesis of the minimum-time problems (value function, switch counts, switching
and dispersal curves over the phase plane) and the bifurcation values of N_kappa."""
