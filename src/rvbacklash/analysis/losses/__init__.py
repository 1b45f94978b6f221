"""Losses and heat (docs/efficiency.md; issue 40): each element's power loss over a revolution from
the elastic solution's loads (``elements``), the efficiency datasheet (``efficiency``: the rated
point, the map, no-load running torque, starting and back-driving torque) and the thermal balance
with the parts' expansion (``thermal``)."""

from rvbacklash.analysis.losses.efficiency import (EfficiencyResult, LossModel, back_driving_torque_nm,
                                                   efficiency_rating, no_load_torque_nm, starting_torque_nm)
from rvbacklash.analysis.losses.elements import ELEMENTS, LossBreakdown, element_losses, loss_context, speeds

__all__ = ["EfficiencyResult", "LossModel", "back_driving_torque_nm", "efficiency_rating", "no_load_torque_nm",
           "starting_torque_nm", "ELEMENTS", "LossBreakdown", "element_losses", "loss_context", "speeds"]
