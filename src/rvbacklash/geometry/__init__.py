"""Geometry formulas of the RV reducer: ratio, pitch radii, K1 (``reducer``) and the exact
modified cycloid profile (``cycloid``). Plain numbers in, plain numbers out."""
