"""Per-design mechanics: stiffnesses that need more than a closed form, computed once per design
and cached (in process and on disk, keyed by the geometry): the cycloid discs' bodies and the
carrier by finite elements (scikit-fem on gmsh meshes). A layer of its own between the problem
and the models: it reads numbers, never a unit, and the models read its results as constants of
the chain (docs/elastic.md)."""
