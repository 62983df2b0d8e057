"""Reports: design tables and figures from a result file."""
