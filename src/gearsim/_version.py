"""The installed version of gearsim (one place, importable from every layer)."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("gearsim")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
