"""The elastic hysteresis model: a unit's torque-angle loop as the test bench measures it
(docs/elastic.md). Three rooms:

- ``chain``: the design's chain of elements in series (``Chain``, ``elastic_model``), each
  element's set of contacts, the angle of each element at a torque and the loop's figures;
- ``solver``: the monotone solves of a set of contacts (the pins with the discs' translations,
  a bearing's rollers) and the warm starts that make a loop cheap;
- ``unit``: one unit, from a contact-model realisation or a measured unit, to its figures
  (``unit_hysteresis``, a production run's batch: ``evaluate_units``);
- ``bodies``: the design's model (``elastic_model``): the closed-form chain with the discs'
  bodies and the carrier by finite elements (``rvbacklash.mechanics``).

The names the rest of the package uses are here.
"""

from rvbacklash.models.elastic.chain import (BACKLASH, ELEMENT_LOST_MOTION, ELEMENTS, FALL, LOST_MOTION, N_ELEMENTS,
                                             N_FIGURES, RIGIDITY, RISE, SHARES, Chain, ElasticModel, closed_form_model,
                                             pin_law_table)
from rvbacklash.models.elastic.bodies import elastic_model
from rvbacklash.models.elastic.unit import (ElasticUnit, LoopDesign, PreparedUnit, evaluate_units, loop_design,
                                            nominal_realization, nominal_unit, other_stages_nominal,
                                            unit_from_realization, unit_hysteresis)

__all__ = ["BACKLASH", "ELEMENT_LOST_MOTION", "ELEMENTS", "FALL", "LOST_MOTION", "N_ELEMENTS", "N_FIGURES", "RIGIDITY", "RISE", "SHARES",
           "Chain", "ElasticModel", "closed_form_model", "ElasticUnit", "LoopDesign", "PreparedUnit", "elastic_model", "evaluate_units",
           "loop_design", "nominal_realization", "nominal_unit", "other_stages_nominal", "pin_law_table",
           "unit_from_realization", "unit_hysteresis"]
