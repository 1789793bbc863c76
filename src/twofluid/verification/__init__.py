"""verification subpackage."""
