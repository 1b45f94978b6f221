"""Analyses over a prepared Problem: stack-up, sensitivity, exact distribution, simulation,
scenarios, nominal contact; each returns a typed result."""
