"""gearsim: mesh stiffness, tooth-root cracks and vibration of spur and helical gear trains."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("gearsim")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
