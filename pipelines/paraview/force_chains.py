"""Renders a gf-xdmf description the way docs/programs/gf-xdmf.md shows it: the grains as
disks of their radius (shaded by their velocity along x: the shear profile), the force chains (contacts coloured by
normal force, on top) and the box outline, at one stored frame.

    xvfb-run -a pvbatch pipelines/paraview/force_chains.py RUN.xdmf2 OUT.png [--frame K] [--size W H]

--frame: index of the stored frame (negative counts from the end; default -1, the last).
Writes OUT.png atomically (a temporary beside it, renamed). Used by the ParaView test
(tests/paraview/xdmf_paraview.sh) and for the picture in docs/images/."""
import argparse
import os

from paraview.simple import (
    ColorBy,
    ExtractBlock,
    GetColorTransferFunction,
    GetScalarBar,
    CreateView,
    SaveScreenshot,
    Show,
    XDMFReader,
)
from paraview import servermanager


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("xdmf")
    parser.add_argument("png")
    parser.add_argument("--frame", type=int, default=-1)
    parser.add_argument("--size", type=int, nargs=2, default=[900, 900], metavar=("W", "H"))
    args = parser.parse_args()

    reader = XDMFReader(FileNames=[os.path.abspath(args.xdmf)])
    reader.UpdatePipelineInformation()
    times = [float(t) for t in reader.TimestepValues]
    time = times[args.frame]

    view = CreateView("RenderView")
    view.ViewSize = args.size
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 0
    view.InteractionMode = "2D"
    view.ViewTime = time

    grains = ExtractBlock(Input=reader, Selectors=["/Root/grains"])
    disks = Show(grains, view)
    disks.SetRepresentationType("Point Gaussian")
    disks.ShaderPreset = "Plain circle"
    disks.ScaleByArray = 1
    disks.UseScaleFunction = 0
    disks.SetScaleArray = ["POINTS", "radius"]
    disks.GaussianRadius = 1.0
    ColorBy(disks, ("POINTS", "velocity", "X"))
    shade = GetColorTransferFunction("velocity")
    shade.ApplyPreset("Grayscale", True)
    shade.AutomaticRescaleRangeMode = "Never"
    shade.VectorMode = "Component"
    shade.VectorComponent = 0
    grains.UpdatePipeline(time)
    low, high = servermanager.Fetch(grains).GetBlock(0).GetPointData().GetArray("velocity").GetRange(0)
    # Light greys only (55 % to 85 % of white from the slowest to the fastest grain), so
    # that the chains stand out and the shear profile still shows.
    span = max(high - low, 1e-30) / 0.3
    shade.RescaleTransferFunction(low - 0.55 * span, low + 0.45 * span)
    disks.SetScalarBarVisibility(view, False)

    box = Show(ExtractBlock(Input=reader, Selectors=["/Root/box"]), view)
    ColorBy(box, None)
    box.AmbientColor = box.DiffuseColor = [0, 0, 0]
    box.LineWidth = 2
    box.Position = [0, 0, 0.2]

    contacts = ExtractBlock(Input=reader, Selectors=["/Root/contacts"])
    chains = Show(contacts, view)
    chains.LineWidth = 3
    chains.Position = [0, 0, 0.1]  # in front of the disks
    ColorBy(chains, ("CELLS", "normal_force"))
    force = GetColorTransferFunction("normal_force")
    force.ApplyPreset("Inferno (matplotlib)", True)
    force.InvertTransferFunction()  # dark for strong contacts, on light disks
    force.AutomaticRescaleRangeMode = "Never"
    contacts.UpdatePipeline(time)
    block = servermanager.Fetch(contacts).GetBlock(0)
    forces = block.GetCellData().GetArray("normal_force") if block is not None else None
    if forces is not None and forces.GetNumberOfTuples() > 0:
        values = sorted(forces.GetValue(t) for t in range(forces.GetNumberOfTuples()))
        # The strongest few per cent saturate: force distributions have long tails.
        force.RescaleTransferFunction(0.0, max(values[int(0.95 * (len(values) - 1))], 1e-30))
        chains.SetScalarBarVisibility(view, True)
        bar = GetScalarBar(force, view)
        bar.Title = "normal force"
        bar.ComponentTitle = ""
        bar.TitleColor = bar.LabelColor = [0, 0, 0]

    view.ResetCamera()
    view.CameraParallelProjection = 1
    view.ResetCamera()
    temporary = os.path.join(
        os.path.dirname(os.path.abspath(args.png)), "." + os.path.basename(args.png) + ".part-%d.png" % os.getpid()
    )
    try:
        SaveScreenshot(temporary, view, ImageResolution=args.size, TransparentBackground=0)
        os.replace(temporary, args.png)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)
    print("force_chains: %s: frame %d of %d (time %g)" % (args.png, times.index(time), len(times), time))


if __name__ == "__main__":
    main()
