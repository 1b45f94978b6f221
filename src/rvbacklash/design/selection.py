"""The design's ``[selection]`` table: selective assembly as the factory runs it for this design,
the same settings as ``--select`` (docs/selective-assembly.md); a ``--select`` given on the command
line replaces the table, ``--select none`` turns it off::

    [selection]
    pins = "5x2um"             # COUNTxWIDTHum, or the class boundaries "-4,-2,0,2,4um"
    rollers = "3x2um"
    noise_um = 0.5             # the measurement's standard uncertainty [um of pin radius]
    play_max_arcmin = 0.0      # the pin rule's window of predicted play [arcmin]
    play_min_arcmin = -0.5     # optional (default: any preload)
    target_arcmin = 0.3        # optional: the roller rule's target (default: the crank bearings' share)

The table is checked here for its form; ``analysis.selection.classes.design_selection`` turns it
into a Selection (the class counts' and widths' ranges, one error naming ``selection.<field>``).
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field

CLASS_PATTERN = r"^\s*(\d+\s*x\s*[0-9.eE+-]+\s*(um)?|[0-9.eE+-]+(\s*,\s*[0-9.eE+-]+)*\s*um)\s*$"


class SelectionInputs(BaseModel):
    """Selective assembly of the pins and the crank needle rollers (module docstring)."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)

    pins: str | None = Field(None, pattern=CLASS_PATTERN, max_length=2000,
                             description="pin diameter classes: COUNTxWIDTHum (e.g. 5x2um) or boundaries (e.g. "
                                         "-4,-2,0,2,4um)")
    rollers: str | None = Field(None, pattern=CLASS_PATTERN, max_length=2000,
                                description="needle roller diameter classes, as pins")
    noise_um: float = Field(0.0, ge=0, le=100, description="standard uncertainty of the measurement [um]")
    play_max_arcmin: float = Field(0.0, ge=-60, le=60, description="upper end of the pin rule's window of predicted "
                                                                   "play [arcmin]")
    play_min_arcmin: float | None = Field(None, ge=-60, le=60, description="lower end of the window [arcmin] "
                                                                           "(default: any preload)")
    target_arcmin: float | None = Field(None, ge=-60, le=60, description="the roller rule's target [arcmin]")

    def select_text(self) -> str:
        """The same settings as a ``--select`` string."""
        items = [f"{k}={v}" for k, v in (("pins", self.pins), ("rollers", self.rollers)) if v is not None]
        if self.noise_um:
            items.append(f"noise={self.noise_um!r}um")
        lo = f"{self.play_min_arcmin!r}:" if self.play_min_arcmin is not None else ""
        items.append(f"play={lo}{self.play_max_arcmin!r}")
        if self.target_arcmin is not None:
            items.append(f"target={self.target_arcmin!r}")
        return ",".join(items)
