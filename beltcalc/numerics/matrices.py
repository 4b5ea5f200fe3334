"""The argument check the matrix kernels of :mod:`beltcalc.numerics` share."""

from __future__ import annotations

import numpy as np

__all__ = ["as_real_square"]


def as_real_square(A, name: str) -> np.ndarray:
    """``A`` as a C-ordered float64 array, checked to be a real, finite square matrix (n, n)
    or stack (..., n, n); no copy where it is one already.

    Parameters
    ----------
    A : array_like
        The matrix or stack
    name : str
        The function the messages name

    Raises
    ------
    TypeError
        A is complex
    ValueError
        A is not square, or has a non-finite entry
    """
    a = np.asarray(A)
    if np.iscomplexobj(a):
        raise TypeError(f"{name}: a real matrix is needed, got dtype {a.dtype}")
    a = np.array(a, dtype=np.float64, order="C", copy=None)
    if a.ndim < 2 or a.shape[-1] != a.shape[-2]:
        raise ValueError(f"{name}: a square matrix (n, n) or a stack (..., n, n) is needed, "
                         f"got shape {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name}: the matrix has a non-finite entry")
    return a
