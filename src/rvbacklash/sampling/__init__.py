"""Input distributions of the raw factor quantities (and, later, the sampling engine)."""
