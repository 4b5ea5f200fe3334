"""Numerical kernels on numpy and the standard library alone, ported from scipy and LAPACK.

Each module keeps the license notice of the code it ports and names the upstream version:

- :mod:`beltcalc.numerics.expm`: the matrix exponential (scipy's ``expm``), with the choice
  of its Pade degree and scaling in :mod:`beltcalc.numerics.expm_degree`;
- :mod:`beltcalc.numerics.balance`: balancing by a diagonal similarity (LAPACK's ``dgebal``);
- :mod:`beltcalc.numerics.scalar`: Brent's root, golden-section and bounded minimum (scipy's
  ``brentq`` and ``minimize_scalar``), and Horner's polynomial.

They are here because importing ``scipy.linalg`` or ``scipy.optimize`` costs a large part of a
command's start-up. :mod:`beltcalc.numerics.matrices` holds the argument check the matrix
kernels share. Nothing here imports the rest of beltcalc.
"""
