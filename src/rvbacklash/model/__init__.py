"""Backlash models: raw factor values (n, 21) [um] -> output backlash (n,) [arcmin]."""
