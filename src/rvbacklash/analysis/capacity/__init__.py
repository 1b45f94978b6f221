"""Capacity and life (docs/capacity.md; issue 37): the loads every element carries over a revolution,
from the elastic solution (``revolution``), the bearings' ratings and lives (``life``), the main
bearings (``main_bearings``), one unit's derived ratings (``unit``), a duty cycle's life (``duty``)
and the design's datasheet (``rating.capacity_rating``).

The wear (issue 38) and losses (issue 40) work read the loads through ``revolution``:
``UnitCapacity(...).loads(torque)`` or ``CrankAngles`` + ``revolution_loads``.
"""

from rvbacklash.analysis.capacity.rating import CapacityResult, capacity_rating
from rvbacklash.analysis.capacity.revolution import (DEFAULT_ANGLES, CrankAngles, RevolutionLoads, load_geometry,
                                                     needle_rollers, revolution_loads)
from rvbacklash.analysis.capacity.trade import (CapacityTrade, TradePoint, WhatIf, capacity_trade,
                                                clearance_what_if, default_what_ifs, modification_what_if)
from rvbacklash.analysis.capacity.unit import UnitCapacity

__all__ = ["CapacityResult", "capacity_rating", "DEFAULT_ANGLES", "CrankAngles", "RevolutionLoads", "load_geometry",
           "needle_rollers", "revolution_loads", "UnitCapacity", "CapacityTrade", "TradePoint", "WhatIf",
           "capacity_trade", "clearance_what_if", "default_what_ifs", "modification_what_if"]
