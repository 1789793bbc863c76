"""twofluid: finite element model of saturated granular material and liquid moving together."""
__version__ = "0.1.0"
__all__ = ["__version__"]
