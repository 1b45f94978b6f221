"""Design input: validated schema, derived geometry, loading from TOML or built-in examples."""
