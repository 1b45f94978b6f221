"""The installed version, without importing anything else of the package."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("rvbacklash")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0"

# Version of the JSON output formats, written into every JSON output as ``schema_version``:
# the major number changes when a field moves or changes meaning, the minor when fields are added.
# CHANGELOG.md records every change; ``rvbacklash schema --output COMMAND`` prints the schema.
SCHEMA_VERSION = "9.0"
