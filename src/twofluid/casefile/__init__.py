"""casefile subpackage."""
