"""The Typer application the commands register on."""

from __future__ import annotations

import sys

import typer

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # help texts are plain: units such as [mm] must show, not vanish as markup
    help="Design-stage backlash, lost motion and tolerance allocation of RV reducers (after Sun et al. 2014).",
)


def _version(value: bool) -> None:
    if value:
        from rvbacklash._version import __version__

        sys.stdout.write(f"rvbacklash {__version__}\n")
        raise typer.Exit(0)


@app.callback()
def _root(version: bool = typer.Option(False, "--version", is_eager=True, callback=_version,
                                       help="Print the version and exit.")) -> None:
    """Design-stage backlash, lost motion and tolerance allocation of RV reducers."""
