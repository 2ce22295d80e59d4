"""The analysis scripts Make runs (steady_state.py, incline_bulk.py, critical_angle.py), also
imported by the figure scripts, the report and the tests as analysis.<name> (with
PYTHONPATH=<repo>/pipelines), so that a figure reads a table with the code that wrote it."""
