"""The one error type a user sees for bad input."""

from __future__ import annotations

_MISSING = object()


class InputError(ValueError):
    """Bad input: names the parameter (a Python parameter such as ``samples``, or a design-file
    field such as ``second_stage.pins``), the offending value and what is allowed.

    The CLI translates parameter names to its flags (``samples`` -> ``--samples``), prints
    ``str(error)`` as one line on stderr and exits with code 2. ``value`` may be omitted
    (e.g. for a missing field).
    """

    def __init__(self, field: str, value: object = _MISSING, allowed: str = ""):
        self.field = field
        self.has_value = value is not _MISSING
        self.value = value if self.has_value else None
        self.allowed = allowed
        super().__init__(self._text())

    def _text(self) -> str:
        shown = f" = {self.value!r}" if self.has_value else ""
        return f"{self.field}{shown}: {self.allowed}"

    def renamed(self, field: str) -> "InputError":
        """The same error naming ``field`` instead (e.g. a CLI flag for a Python parameter)."""
        return InputError(field, self.value, self.allowed) if self.has_value else InputError(field, allowed=self.allowed)
