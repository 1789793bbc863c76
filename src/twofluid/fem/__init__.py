"""fem subpackage."""
