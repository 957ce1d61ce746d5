"""The engineering verdict (NTC 2018 and its Circolare 2019, C8.7.1): the kinematic quantities
of a mechanism, its capacity curve at finite displacements, the seismic demand, the code
check, and the mirror symmetry that halves a sweep of load directions."""
