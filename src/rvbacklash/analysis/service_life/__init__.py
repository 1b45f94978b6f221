"""Precision over the service life (docs/service-life.md; issue 38): Archard wear of the cycloid
flanks, the pins and their seats and the crank needle bearings from the elastic solution's loads
(``rates``), the worn unit read back by the contact and elastic models (``worn``), the nominal
unit's time stepping (``stepping``), the production run's yield and accuracy life
(``production``), the calibration of the wear coefficient (``calibration``) and the typed results
(``results``).
"""

from rvbacklash.analysis.service_life.rates import WearGeometry, WearIncrement, wear_geometry, wear_per_revolution
from rvbacklash.analysis.service_life.stepping import Trajectory, nominal_trajectory
from rvbacklash.analysis.service_life.worn import WornAngles, worn_unit

__all__ = ["WearGeometry", "WearIncrement", "wear_geometry", "wear_per_revolution", "Trajectory",
           "nominal_trajectory", "WornAngles", "worn_unit"]
