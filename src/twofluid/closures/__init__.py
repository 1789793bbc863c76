"""closures subpackage."""
