"""report --size SIZE --output REPORT.md [chapter options] PACKING.h5...: the reproduction
summary, our numbers beside the thesis' where it gives them. Each chapter adds its section."""
import argparse
import os

import h5py

from granflow.outputs import write_text
from report import ch4, ch4_incline, ch5, ch6_kinetic, ch6_network, ch6_stz, render
from report.steps import read_step_classes, step_note


def packing_rows(paths):
    """Per packing: file name, N, target and achieved ν, largest overlap in mean diameters, seed."""
    rows = []
    for path in paths:
        with h5py.File(path, "r") as f:
            a = f["/parameters"].attrs
            obs = f["/observables"]
            rows.append(
                (
                    os.path.basename(path),
                    len(f["/particles/grains/radius"]),
                    float(a["packing-fraction"]),
                    float(obs["packing_fraction/value"][0]),
                    float(obs["max_overlap/value"][0]) / float(a["mean-diameter"]),
                    int(a["seed"]),
                )
            )
    return rows


def parse(argv=None):
    """The command line, with the options that go together checked."""
    ap = argparse.ArgumentParser(prog="report", description=__doc__)
    ap.add_argument("--size", required=True)
    ap.add_argument("--output", required=True)
    ap.add_argument("--ch4-sweep", help="steady_state.py table of the ν × e sweep (Figs 4.4-4.6)")
    ap.add_argument("--ch4-bagnold", help="steady_state.py table of the Fig 4.2 runs")
    ap.add_argument("--ch4-reference", help="the Fig 4.3 run")
    ap.add_argument("--ch5-correlate", help="gf-correlate table of the chapter-5 sweep (Figs 5.2-5.10)")
    ap.add_argument("--ch5-clusters", help="gf-correlate table of the Fig 5.1 cluster windows")
    ap.add_argument("--ch5-jamming", help="jamming_point.py table (ν_c from the steady stresses)")
    ap.add_argument("--ch4-incline", help="incline_bulk.py table of the incline runs (Figs 4.8-4.10)")
    ap.add_argument("--ch4-critical", help="critical_angle.py table (θ_c)")
    ap.add_argument("--ch6-kinetic", help="gf-kinetic table of the chapter-6 runs (Figs 6.1-6.3)")
    ap.add_argument("--ch6-network", help="gf-network table of the chapter-6 runs (Figs 6.5-6.8)")
    ap.add_argument("--ch6-network-halfstep", help="gf-network table of the half-step runs and their pairs (Fig 6.7)")
    ap.add_argument("--ch6-stz", help="gf-stz fit table (Figs 6.10-6.11)")
    ap.add_argument("--ch6-d2min", help="d2min_maps.py table of the Fig. 6.9 maps")
    ap.add_argument("--step-classes", help="convergence.py --classes-csv output: each section's step dependence")
    ap.add_argument("packings", nargs="+")
    args = ap.parse_args(argv)
    shear = (args.ch4_sweep, args.ch4_bagnold, args.ch4_reference)
    if any(shear) and not all(shear):
        ap.error("--ch4-sweep, --ch4-bagnold and --ch4-reference go together")
    if args.ch6_kinetic and not args.ch5_correlate:
        ap.error("--ch6-kinetic needs --ch5-correlate (ξ/ξ_el of its runs)")
    if args.ch6_network_halfstep and not args.ch6_network:
        ap.error("--ch6-network-halfstep needs --ch6-network")
    if bool(args.ch4_incline) != bool(args.ch4_critical):
        ap.error("--ch4-incline and --ch4-critical go together")
    return args


def sections(args):
    """(name, function of no argument giving its lines) of each section the options ask for, in
    the report's order; the name keys its step dependence (steps.SECTION_OBSERVABLES)."""
    a = args
    wanted = [
        ("ch4", a.ch4_sweep, lambda: ch4.section(a.ch4_sweep, a.ch4_bagnold, a.ch4_reference)),
        ("incline", a.ch4_incline, lambda: ch4_incline.section(a.ch4_incline, a.ch4_critical, a.ch4_sweep)),
        ("ch5", a.ch5_correlate, lambda: ch5.section(a.ch5_correlate, a.ch5_clusters)),
        ("ch5_jamming", a.ch5_jamming, lambda: ch5.jamming_section(a.ch5_jamming)),
        ("ch6_kinetic", a.ch6_kinetic, lambda: ch6_kinetic.section(a.ch6_kinetic, a.ch5_correlate)),
        ("ch6_network", a.ch6_network, lambda: ch6_network.section(a.ch6_network, a.ch6_network_halfstep)),
        ("ch6_d2min", a.ch6_d2min, lambda: ch6_stz.d2min_section(a.ch6_d2min)),
        ("ch6_stz", a.ch6_stz, lambda: ch6_stz.stz_section(a.ch6_stz, a.ch4_critical)),
    ]
    return [(name, make) for name, given, make in wanted if given]


def main(argv=None):
    args = parse(argv)
    lines = render.page_head(args.size) + render.packings(packing_rows(args.packings))
    classes = read_step_classes(args.step_classes) if args.step_classes else None
    for name, make in sections(args):
        lines += make() + step_note(classes, name, args.step_classes)
    write_text(args.output, "\n".join(lines) + "\n")
