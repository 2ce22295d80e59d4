"""`python3 pipelines/report ARGS`: the report's command line (report/cli.py)."""
import os
import sys

if not __package__:
    # Run as a directory: its parent, pipelines/, goes on the path in its place, so that the
    # package imports as `report` beside `analysis`, as with `python3 -m report`.
    sys.path[0] = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

from report.cli import main  # noqa: E402

main()
