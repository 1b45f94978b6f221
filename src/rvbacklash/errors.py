"""The one error type a user sees for bad input."""

from __future__ import annotations

_MISSING = object()


class InputError(ValueError):
    """Bad input: names the field, the offending value and what is allowed.

    The CLI prints ``str(error)`` as one line on stderr and exits with code 2.
    ``value`` may be omitted (e.g. for a missing field).
    """

    def __init__(self, field: str, value: object = _MISSING, allowed: str = ""):
        self.field = field
        self.value = None if value is _MISSING else value
        self.allowed = allowed
        shown = "" if value is _MISSING else f" = {value!r}"
        super().__init__(f"{field}{shown}: {allowed}")
