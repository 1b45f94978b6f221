"""Backlash models over a prepared Problem: ``linear`` (Eq. (1)/(2)), ``contact`` (exact
cycloid-pin geometry, per-pin errors)."""
