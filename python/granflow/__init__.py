"""granflow: granflow's files and statistics from Python (docs/python.md).

For users:
- granflow.Trajectory (granflow.trajectory): a trajectory of gf-pack, gf-shear or gf-incline,
  read lazily frame by frame: positions, velocities, angular velocities, radii, the
  Lees–Edwards box and the frame's contacts, as NumPy arrays.
- granflow.read_table (granflow.tables): any analysis table (gf-correlate, gf-kinetic,
  gf-network, gf-stz, the pipelines' tables) as named arrays with their units and meanings.
- granflow.statistics: the steady-state rule (MSER), the blocking error, the halves change
  and the block jackknife of the C++ library lib/statistics, through its C API (the package
  ships the library; `import granflow.statistics`).

What the pipeline scripts (pipelines/) share besides: HDF5 reading (granflow.hdf5), atomic
outputs and tables with provenance (granflow.outputs), disks drawn with their periodic and
Lees–Edwards images (granflow.disks), the plot scripts' preamble (granflow.plotting), and the
readers of the programs' tables for the figures and the report (granflow.correlation_table,
kinetic_table, network_table, stz_table).

Installed with `pip install ./python` (docs/python.md); the pipelines use it from the
repository with PYTHONPATH=<repo>/python, which Makefile.sweeps and ctest set."""
from granflow.tables import Column, Group, Table, read_table
from granflow.trajectory import Box, Contacts, Frame, Trajectory

__all__ = ["Box", "Column", "Contacts", "Frame", "Group", "Table", "Trajectory", "read_table"]
