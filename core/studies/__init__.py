"""Design studies: many variants of one design evaluated at once.

What goes here: batch kernels that solve a linkage for D designs × N samples in one layout
(positions, rates, validity, assembly-mode continuity, transmission angles, kinetostatics), and
the studies built on them — parameter sweeps (grid or Sobol), tolerance and pin-clearance Monte
Carlo with first-order (linearised) bands, sensitivity, and single- or multi-objective
optimisation. Work is cut into chunks bounded by the memory budget; chunks run in this process or
on a Dask cluster, and the same seed gives the same numbers whatever runs them. Layer: above
``analyses`` (it evaluates them), below ``design`` (synthesis searches with it) and ``io``.
"""
