"""granflow_py: what the pipeline scripts share. HDF5 reading (granflow_py.hdf5), atomic
outputs and tables with provenance (granflow_py.outputs), disks drawn with their periodic and
Lees–Edwards images (granflow_py.disks), the plot scripts' preamble (granflow_py.plotting) and
the reader of gf-correlate's output (granflow_py.correlation_table), and the steady-state rule
and error estimators of the C++ library lib/statistics (granflow_py.statistics).

The scripts find it with PYTHONPATH=<repo>/pipelines, which Makefile.sweeps and ctest set."""
