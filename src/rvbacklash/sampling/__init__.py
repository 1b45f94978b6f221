"""Monte-Carlo sampling: the seeded block engine, the input transform (copula) and the compiled
block sources of the models."""
