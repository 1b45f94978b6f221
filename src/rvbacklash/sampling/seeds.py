"""The seed every entry point takes (docs/architecture.md, "Randomness"): one check, one message."""

from __future__ import annotations

import numpy as np

from rvbacklash.errors import InputError


def check_seed(seed) -> int:
    """``seed`` as an int: a whole number >= 0 (numpy's SeedSequence takes no negative entropy),
    else the InputError every command gives for ``--seed``."""
    if seed is None or isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("seed", seed, "allowed: an integer >= 0")
    return int(seed)
