"""Tolerances from precision grades: ISO 1328-1 (1995, 2013), ISO 1328-2, ISO 286-1/-2, and the
documented assumption used for the cycloid stage (no public text of JB/T 10419-2005)."""
