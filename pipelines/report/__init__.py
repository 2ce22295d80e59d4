"""The reproduction report, figures/REPORT.md: our numbers beside the thesis' where it gives them.

Run as `python3 pipelines/report --size SIZE --output REPORT.md [chapter options] PACKING.h5...`
(or `python3 -m report` with pipelines/ on the path); `--help` lists the options.

Modules: cli (the command line and the order of the sections), render (numbers with errors, block
quotes, tables, the page's head and the packings), thesis (the quoted sentences, as data), steps
(each section's step dependence from the convergence study's classes), and one per chapter or
part of one, each a function `section(...)` of the table paths built from pure checks of the
tables and their lines: ch4 (simple shear), ch4_incline (incline flow and θ_c), ch5
(microstructure, and ν_c from the stresses: `jamming_section`), ch6_kinetic, ch6_network, ch6_stz
(the D²min maps, `d2min_section`, and the STZ law, `stz_section`)."""
