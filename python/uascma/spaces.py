"""The spaces of uascma.Environment: Gymnasium's own when the gymnasium package is installed, else a
``Discrete`` with the same behaviour for what the environment uses (``n``, ``start``, ``shape``, ``dtype``,
``sample(mask=None)``, ``contains``, ``seed``, ``==``, ``repr``), so code written for Gymnasium runs with or
without it.
"""
import numpy as np

try:  # pragma: no cover - depends on the machine
    from gymnasium.spaces import Discrete as _GymDiscrete
except ImportError:  # the package is optional
    _GymDiscrete = None

HAVE_GYMNASIUM = _GymDiscrete is not None


class _Discrete:
    """{start, start + 1, …, start + n − 1}: Gymnasium's Discrete(n, start=0), for machines without gymnasium."""

    def __init__(self, n, seed=None, start=0):
        n = int(n)
        if n <= 0:
            raise ValueError(f"Discrete: n: a positive number of elements, got {n}")
        self.n = np.int64(n)
        self.start = np.int64(start)
        self.shape = ()
        self.dtype = np.dtype(np.int64)
        self._np_random = None
        if seed is not None:
            self.seed(seed)

    @property
    def np_random(self):
        if self._np_random is None:
            self.seed()
        return self._np_random

    def seed(self, seed=None):
        """Seeds the space's own generator (numpy.random.Generator); returns [seed] as Gymnasium does."""
        seed_sequence = np.random.SeedSequence(seed)
        self._np_random = np.random.Generator(np.random.PCG64(seed_sequence))
        return [seed if seed is not None else int(seed_sequence.entropy)]

    def sample(self, mask=None):
        """A uniformly drawn element (np.int64); with mask (int8 array of n, 1 = allowed) among the allowed,
        ``start`` when none is."""
        if mask is None:
            return self.start + self.np_random.integers(self.n)
        mask = np.asarray(mask)
        if mask.dtype != np.int8 or mask.shape != (int(self.n),) or not np.all((mask == 0) | (mask == 1)):
            raise ValueError(f"Discrete.sample: mask: an int8 array of shape ({int(self.n)},) of 0 and 1, got {mask!r}")
        allowed = np.flatnonzero(mask)
        if allowed.size == 0:
            return self.start
        return self.start + np.int64(self.np_random.choice(allowed))

    def contains(self, x):
        if isinstance(x, (int, np.integer)) and not isinstance(x, bool):
            value = np.int64(x)
        elif isinstance(x, np.ndarray) and x.shape == () and np.issubdtype(x.dtype, np.integer):
            value = np.int64(x.item())
        else:
            return False
        return bool(self.start <= value < self.start + self.n)

    def __contains__(self, x):
        return self.contains(x)

    def __eq__(self, other):
        return isinstance(other, _Discrete) and self.n == other.n and self.start == other.start

    def __repr__(self):
        return f"Discrete({int(self.n)})" if self.start == 0 else f"Discrete({int(self.n)}, start={int(self.start)})"

    @property
    def is_np_flattenable(self):
        return True


Discrete = _GymDiscrete if HAVE_GYMNASIUM else _Discrete
