"""Confidence bounds of a share seen in samples, in closed form (``math`` only).

A pair in collision in ``k`` of ``n`` independent uniform samples has the share ``k/n``
of the sampled configuration space. `wilson` is its 95% Wilson score interval;
`clopper_pearson_upper` is the exact upper bound when ``k = 0``, the only case where
the exact interval has a closed form.
"""

import math

Z95 = 1.959963984540054
"""The standard normal quantile of 0.975: a two-sided 95% interval."""


def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """The Wilson score interval of ``k`` successes in ``n`` trials.

    Raises:
        ValueError: ``n < 1`` or ``k`` outside ``[0, n]``.
    """
    if n < 1 or not 0 <= k <= n:
        raise ValueError(f"no share of {k} in {n} samples")
    p = k / n
    z2 = z * z
    centre = (p + z2 / (2 * n)) / (1 + z2 / n)
    half = z / (1 + z2 / n) * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n))
    low = 0.0 if k == 0 else max(0.0, centre - half)
    high = 1.0 if k == n else min(1.0, centre + half)
    return low, high


def clopper_pearson_upper(n: int, alpha: float = 0.05, *, two_sided: bool = True) -> float:
    """The exact (Clopper-Pearson) upper bound of the share when none of ``n`` samples hit.

    ``1 - (alpha/2)^(1/n)`` for the two-sided interval, ``1 - alpha^(1/n)`` (about
    ``3/n`` at 95%) for the one-sided bound.

    Raises:
        ValueError: ``n < 1`` or ``alpha`` outside ``(0, 1)``.
    """
    if n < 1 or not 0.0 < alpha < 1.0:
        raise ValueError(f"no bound for {n} samples at alpha {alpha}")
    tail = alpha / 2 if two_sided else alpha
    return -math.expm1(math.log(tail) / n)
