"""timestepping subpackage."""
