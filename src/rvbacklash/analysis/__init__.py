"""Analyses over a model and the factor distributions: stack-up, sensitivity."""
